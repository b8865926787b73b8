#!/usr/bin/env bash
# plot_python.sh NOETHER SOURCE_DIR WORK_DIR: plot scripts run with the python3 on the PATH
# (a user's virtual environment) and an argument vector, not a shell string: a fake python3
# first on the PATH records its arguments, and a file name with a quote and a space reaches
# it intact, and Debian's python3 takes over when the PATH's has no matplotlib. Fails on a driver that runs /usr/bin/python3 or builds a quoted shell command.
set -u
noether=$1; src=$2; work=$3
fail() { echo "plot_python: FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work/bin" && cd "$work" || exit 1
cat > bin/python3 <<'PY'
#!/bin/sh
for a in "$@"; do printf '%s\n' "$a"; done > "$(dirname "$0")/../called-with"
PY
chmod +x bin/python3
PATH="$work/bin:$PATH" "$noether" compare "$src/examples/kepler-jm.yaml" --set run.t_end=1 \
  --run '{plugin: lgvi, step: 0.01}' --repeats 1 -o "it's a table.csv" --h5 t.h5 --plot "it's a plot.png" \
  > out.txt 2>&1 || fail "compare failed: $(cat out.txt)"
[ -f called-with ] || fail "the python3 on the PATH was not run: $(cat out.txt)"
grep -qx "it's a table.csv" called-with || fail "arguments: $(cat called-with)"
grep -qx "it's a plot.png" called-with || fail "arguments: $(cat called-with)"
grep -q "plot_compare.py$" called-with || fail "arguments: $(cat called-with)"
grep -qx "kepler-jm.yaml" called-with || fail "the title is not the scene's file name: $(cat called-with)"
# A python3 on the PATH without matplotlib (the scripts exit 3): Debian's draws the plot.
printf '#!/bin/sh\nexit 3\n' > bin/python3
PATH="$work/bin:$PATH" "$noether" compare "$src/examples/kepler-jm.yaml" --set run.t_end=1 \
  --run '{plugin: lgvi, step: 0.01}' --repeats 1 -o t.csv --h5 t.h5 --plot fallback.png \
  > out2.txt 2>&1 || fail "compare failed: $(cat out2.txt)"
[ -s fallback.png ] || fail "no plot from the fallback python: $(cat out2.txt)"
echo "plot_python: the PATH's python3 ran plot_compare.py with $(wc -l < called-with) intact arguments; \
/usr/bin/python3 drew the plot when the PATH's had no matplotlib"
