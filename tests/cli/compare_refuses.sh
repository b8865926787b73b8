#!/usr/bin/env bash
# compare_refuses.sh NOETHER SOURCE_DIR WORK_DIR: `noether compare` does not overwrite a table or
# plot unless --force is given (like `noether run`): exit 2 naming the file, before any run, and
# the file keeps its bytes; with --force it is replaced. -o alone names the HDF5 table too.
set -u
noether=$1; src=$2; work=$3
fail() { echo "compare_refuses: FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
echo keep > table.csv
args=(compare "$src/examples/kepler-jm.yaml" --set run.t_end=1 --run '{plugin: lgvi, step: 0.01}' --repeats 1
      -o table.csv --h5 table.h5 --no-plot)
"$noether" "${args[@]}" > out.txt 2>&1; rc=$?
[ "$rc" -eq 2 ] || fail "exit $rc: $(cat out.txt)"
grep -q "table.csv exists; noether does not overwrite output unless asked: pass --force" out.txt || fail "$(cat out.txt)"
[ "$(cat table.csv)" = keep ] || fail "table.csv was changed"
[ ! -e table.h5 ] || fail "table.h5 was written: the comparison ran"
"$noether" "${args[@]}" --force > out.txt 2>&1 || fail "--force: $(cat out.txt)"
grep -q "^lgvi" table.csv || fail "table.csv not replaced: $(cat table.csv)"
mkdir -p out
"$noether" compare "$src/examples/kepler-jm.yaml" --set run.t_end=1 --run '{plugin: lgvi, step: 0.01}' --repeats 1 \
  -o out/named.csv --no-plot > out.txt 2>&1 || fail "-o alone: $(cat out.txt)"
[ -s out/named.csv ] && [ -s out/named.h5 ] || fail "-o out/named.csv did not give out/named.h5: $(ls out)"
[ ! -e kepler-jm-compare.h5 ] || fail "-o given, yet the HDF5 table went to kepler-jm-compare.h5"
grep -q "table: out/named.csv, out/named.h5" out.txt || fail "$(cat out.txt)"
echo "compare_refuses: an existing table refused with exit 2 and kept; replaced with --force; -o names the HDF5 table"
