#!/usr/bin/env bash
# `pip install .` as README shows it (docs/python.md, "pip install"), from a fresh copy of the
# source tree into a new virtual environment, offline:
#   python3 -m venv --system-site-packages v && v/bin/pip install . && v/bin/noether run examples/dumbbells.yaml
# then checks that the installed driver prints what the build tree's prints (its whole summary but
# the wall time), lists the same plugins, that `import noether` in the venv is the venv's module
# and loads every plugin without a warning, that an out-of-tree plugin builds against the venv as
# an install prefix, and that `pip uninstall noether` leaves no file of noether behind.
#   pip_install.sh SOURCE_DIR BUILD_DIR
# The copy holds git's tracked files as they are in the working tree (what a clone of the next
# commit holds; nothing untracked or built can help). The wheel's build compiles every source of
# the copy — through ccache when it is installed, which hits the release build's objects for the
# files that are the same (~1 min), from scratch without it (~4.5 min of two cores) — hence the
# label slow (CI's budget, docs/reliability.md).
set -euo pipefail
src=$1 build=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir "$work/src"
if git -C "$src" rev-parse --git-dir > /dev/null 2>&1; then
  git -C "$src" ls-files -z | (cd "$src" && xargs -0 tar -cf - --no-recursion) | tar -xf - -C "$work/src"
else
  (cd "$src" && tar -cf - --exclude=./build .) | tar -xf - -C "$work/src"
fi
cd "$work/src"
# The backend's source distribution (PEP 517's build_sdist, as `python3 -m build` would call it):
# every file of the copy, under noether-<version>/, with PKG-INFO.
find . -type f | sed 's|^\./||' | sort > "$work/files.txt"
sdist=$(/usr/bin/python3 -c "import sys; sys.path.insert(0, 'python/packaging'); import noether_build; print(noether_build.build_sdist('$work'))")
tar -tzf "$work/$sdist" | sed 's|^[^/]*/||' | grep -v '^PKG-INFO$' | sort > "$work/sdist.txt"
diff "$work/files.txt" "$work/sdist.txt" > /dev/null || { echo "FAIL: $sdist does not hold the source tree"; diff "$work/files.txt" "$work/sdist.txt" | head; exit 1; }
# (Into a file first: `tar … | grep -q` fails under pipefail whenever grep stops reading before tar
# has written the whole PKG-INFO, which holds the README: tar dies of SIGPIPE.)
tar -xzOf "$work/$sdist" "${sdist%.tar.gz}/PKG-INFO" > "$work/PKG-INFO"
grep -q "^Name: noether$" "$work/PKG-INFO" || { echo "FAIL: $sdist's PKG-INFO does not name noether"; exit 1; }
echo "sdist: $sdist, $(wc -l < "$work/sdist.txt") files"
/usr/bin/python3 -m venv --system-site-packages "$work/v"
start=$(date +%s)
# PIP_NO_INDEX: anything pip would fetch fails the test instead of being fetched.
PIP_NO_INDEX=1 PIP_DISABLE_PIP_VERSION_CHECK=1 "$work/v/bin/pip" install . > "$work/pip.log" 2>&1 \
  || { tail -40 "$work/pip.log"; echo "FAIL: pip install . (log above)"; exit 1; }
echo "pip install . (configure, build, wheel, install): $(($(date +%s) - start)) s"
grep -E "^Successfully installed noether-" "$work/pip.log"

# The driver on the venv's PATH, against the build tree's: the same summary, wall time aside.
PATH="$work/v/bin:$PATH" noether run examples/dumbbells.yaml --no-progress > "$work/venv.txt"
"$build/bin/noether" run examples/dumbbells.yaml --no-progress > "$work/tree.txt"
grep -v "wall time" "$work/venv.txt" > "$work/venv.cmp"
grep -v "wall time" "$work/tree.txt" > "$work/tree.cmp"
diff "$work/tree.cmp" "$work/venv.cmp" || { echo "FAIL: the venv's noether prints another summary"; exit 1; }
grep -E "^(max \|E - E0\||verdict)" "$work/venv.txt"

"$work/v/bin/noether" plugins | awk 'NF && $1 ~ /^(potential|integrator|force)$/ {print $1, $2}' | sort > "$work/venv-plugins.txt"
"$build/bin/noether" plugins | awk 'NF && $1 ~ /^(potential|integrator|force)$/ {print $1, $2}' | sort > "$work/tree-plugins.txt"
diff "$work/tree-plugins.txt" "$work/venv-plugins.txt" || { echo "FAIL: the venv's noether finds other plugins"; exit 1; }
echo "plugins in the venv: $(wc -l < "$work/venv-plugins.txt"), as in the build tree"

# Python from the venv, outside the source tree: its module, every plugin loaded (a plugin that
# does not load is a RuntimeWarning, made an error here), a run, and a file the venv's driver wrote.
cd "$work"
PATH="$work/v/bin:$PATH" noether run "$work/src/examples/dumbbells.yaml" --set run.t_end=1 -o "$work/d.h5" --no-progress > /dev/null
"$work/v/bin/python" -W error::RuntimeWarning -c "
import noether
assert noether.__file__.startswith('$work/v/'), noether.__file__
names = sorted(p['kind'] + ' ' + p['name'] for p in noether.plugins())
expected = open('$work/venv-plugins.txt').read().split('\n')[:-1]
assert names == expected, (names, expected)
sim = noether.Simulation('$work/src/examples/dumbbells.yaml', set=['run.t_end=1'])
sim.integrate(1.0)
out = noether.read('$work/d.h5')
import numpy as np
assert np.array_equal(out['positions'][-1], sim.positions), 'the module and the driver disagree'
print('import noether:', noether.__file__, '- plugins', len(names), '- t = 1 as the driver wrote it')
"

# An out-of-tree plugin against the venv as an install prefix (its headers and CMake package).
cmake -S "$work/src/examples/custom-force" -B "$work/force" -G Ninja -DCMAKE_PREFIX_PATH="$work/v" > "$work/force.log"
cmake --build "$work/force" >> "$work/force.log"
NOETHER_PLUGIN_PATH="$work/force" "$work/v/bin/noether" plugins | grep -E '^force +linear-drag'

# pip uninstall removes every file it installed.
"$work/v/bin/pip" uninstall -y noether > "$work/uninstall.log"
left=$(find "$work/v" \( -name '*noether*' -o -path '*/include/noether/*' \) -not -type d | head -5)
[ -z "$left" ] || { echo "FAIL: pip uninstall left files of noether:"; echo "$left"; exit 1; }
[ ! -e "$work/v/bin/noether" ]
if "$work/v/bin/python" -c "import noether" 2> /dev/null; then echo "FAIL: noether still imports"; exit 1; fi
echo "pip uninstall noether: no file of noether left in the venv"
