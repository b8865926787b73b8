#!/usr/bin/env bash
# refine_verify.sh NOETHER SOURCE_DIR WORK_DIR: the closure `orbit refine` reports for the
# orbit it writes is the closure `orbit verify` measures on that file (they once differed:
# 5.4e-14 printed, 2.0e-12 verified, because refine measured along its variational flow).
set -u
noether=$1; src=$2; work=$3
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
refined=$("$noether" orbit refine "$src/examples/orbits/figure-eight-3.yaml" -o refined.yaml) || { echo "$refined"; exit 1; }
after=$(sed -n 's/^closure [^ ]* -> \([^ ]*\) in .*/\1/p' <<<"$refined")
verified=$("$noether" orbit verify refined.yaml | sed -n 's/^closure ||xi(T) - xi(0)|| = \([^ ]*\) .*/\1/p')
echo "refine reports $after, verify measures $verified"
[ -n "$after" ] && [ "$after" = "$verified" ] || { echo "refine_verify: FAIL"; exit 1; }
