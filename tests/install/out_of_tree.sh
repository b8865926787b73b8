#!/usr/bin/env bash
# The out-of-tree plugin workflow as a user meets it: install noether to a fresh prefix, build
# examples/custom-potential, examples/custom-integrator and examples/custom-force against the
# installed package only, list them with the installed driver, and run each example's own tests
# (the J2 nodal precession against the analytic rate, check-potential; Störmer–Verlet's order and
# bounded energy error, its refusal of rigid bodies; linear drag against its exact decay).
#   out_of_tree.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
# The licence is installed with it (README.md, "Licence").
grep -q "^BSD 3-Clause License$" "$work/prefix/share/doc/noether/LICENSE"
start=$(date +%s.%N)
cmake -S "$src/examples/custom-potential" -B "$work/build" -G Ninja \
      -DCMAKE_PREFIX_PATH="$work/prefix" > "$work/configure.log"
cmake --build "$work/build"
end=$(date +%s.%N)
printf 'out-of-tree configure + build: %.1f s\n' "$(echo "$end - $start" | bc)"
NOETHER_PLUGIN_PATH="$work/build" "$work/prefix/bin/noether" plugins | tee "$work/plugins.txt"
grep -Eq '^potential +j2 +point masses plus the J2' "$work/plugins.txt"
grep -Eq 'radius +reference' "$work/plugins.txt"
ctest --test-dir "$work/build" --output-on-failure
# The out-of-tree integrator, the same way.
cmake -S "$src/examples/custom-integrator" -B "$work/integrator" -G Ninja \
      -DCMAKE_PREFIX_PATH="$work/prefix" > "$work/configure-integrator.log"
cmake --build "$work/integrator"
NOETHER_PLUGIN_PATH="$work/integrator" "$work/prefix/bin/noether" plugins | grep -E '^integrator +stormer-verlet'
ctest --test-dir "$work/integrator" --output-on-failure
# The out-of-tree force, the same way.
cmake -S "$src/examples/custom-force" -B "$work/force" -G Ninja \
      -DCMAKE_PREFIX_PATH="$work/prefix" > "$work/configure-force.log"
cmake --build "$work/force"
NOETHER_PLUGIN_PATH="$work/force" "$work/prefix/bin/noether" plugins | grep -E '^force +linear-drag'
ctest --test-dir "$work/force" --output-on-failure
# The out-of-tree plugins link the installed libnoether-core only, and only its interface.
core=$(find "$work/prefix" -name 'libnoether-core.so' -print -quit)
"$src/tests/abi/check_plugin_abi.sh" "$core" "$work/build/noether-j2.so" | tail -1
"$src/tests/abi/check_plugin_abi.sh" "$core" "$work/integrator/noether-stormer-verlet.so" | tail -1
"$src/tests/abi/check_plugin_abi.sh" "$core" "$work/force/noether-linear-drag.so" | tail -1
# The Python module from the prefix: found there (<prefix>/<libdir>/python3/dist-packages), it
# finds the installed libnoether and plugins, and also the out-of-tree one on NOETHER_PLUGIN_PATH.
if [ -n "$(find "$work/prefix" -path '*python3/dist-packages/noether/__init__.py')" ]; then
  pydir=$(dirname "$(dirname "$(find "$work/prefix" -path '*python3/dist-packages/noether/__init__.py' -print -quit)")")
  cd "$work"  # not the source tree: nothing found by accident
  NOETHER_PLUGIN_PATH="$work/build" PYTHONPATH="$pydir" /usr/bin/python3 -c "
import noether
names = [p['name'] for p in noether.plugins()]
assert 'lgvi' in names and 'j2' in names, names
assert noether.__file__.startswith('$work/prefix'), noether.__file__
sim = noether.Simulation('$src/examples/dumbbells.yaml', set=['run.t_end=1'])
sim.integrate(1)
print('python from the prefix:', noether.__file__, 'max|dE| %.4e' % sim.summary()['max_abs_energy_error'])
"
fi
