#!/usr/bin/env bash
# plot_python.sh NOETHER SOURCE_DIR WORK_DIR: plot scripts run with Debian's /usr/bin/python3
# (README, "Python": one interpreter), whatever python3 comes first on the PATH, with an argument
# vector, not a shell string: a fake python3 first on the PATH (a venv without matplotlib) is
# never run and nothing says "matplotlib is not available"; a file name with a quote and a space
# reaches the script intact (the plot is drawn under that name).
set -u
noether=$1; src=$2; work=$3
fail() { echo "plot_python: FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work/bin" && cd "$work" || exit 1
cat > bin/python3 <<'PY'
#!/bin/sh
for a in "$@"; do printf '%s\n' "$a"; done > "$(dirname "$0")/../called-with"
echo "matplotlib is not available" >&2
exit 3
PY
chmod +x bin/python3
PATH="$work/bin:$PATH" "$noether" compare --force "$src/examples/kepler-jm.yaml" --set run.t_end=1 \
  --run '{plugin: lgvi, step: 0.01}' --repeats 1 -o "it's a table.csv" --h5 t.h5 --plot "it's a plot.png" \
  > out.txt 2>&1 || fail "compare failed: $(cat out.txt)"
[ ! -f called-with ] || fail "the python3 on the PATH was run: $(cat called-with)"
[ -s "it's a plot.png" ] || fail "no plot under the quoted name: $(cat out.txt)"
grep -q "plot: it's a plot.png" out.txt || fail "the plot is not reported: $(cat out.txt)"
if grep -q "not available" out.txt; then fail "a message about another interpreter: $(cat out.txt)"; fi
echo "plot_python: /usr/bin/python3 drew \"it's a plot.png\"; the PATH's python3 was not run"
