#!/usr/bin/env bash
# Fuzzes the scene parser and validator with libFuzzer (clang, ASan + UBSan): builds the
# sanitize preset's fuzz target, seeds it with every example and test scene, and runs it for
# RUNS executions (default 100000) or SECONDS of wall time (default 1500), whichever comes
# first. Exits non-zero on any crash, hang (> 10 s for one input), leak or sanitizer report;
# prints the executions and executions per second. Used by the slow test fuzz.scene-parser.
#   tools/fuzz.sh [RUNS] [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-100000}
seconds=${2:-1500}
./tools/install-deps.sh --sanitize > /dev/null
cmake --preset sanitize > /dev/null
cmake --build --preset sanitize --target noether_fuzz_scene
work=build/sanitize/fuzz
rm -rf "$work" && mkdir -p "$work/corpus" "$work/findings"
cp examples/*.yaml examples/orbits/*.yaml tests/cli/scenes/*.yaml "$work/corpus/"
# Not the scenes of KW4's radar meshes and of the Didymos mesh (thousands of faces, 0.2–1 s per
# input under the sanitizers; kw4-alpha-orbiter.yaml in the corpus cut the rate from 211 to 69
# inputs a second; a mutant of didymos-spacecraft.yaml that moved Dimorphos inside Didymos took
# 12 s — 2000 surface samples against 1996 faces in the overlap check — and failed the run as a
# slow unit): mesh reading is fuzzed through the small meshes of tests/cli/scenes, particles
# through tests/cli/scenes/particles-inside.yaml.
grep -l -e "a66391_1999kw4" -e "Didymos_A" "$work"/corpus/*.yaml | xargs rm -f
log=$work/fuzz.log
status=0
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  build/sanitize/bin/noether_fuzz_scene -runs="$runs" -max_total_time="$seconds" -timeout=10 \
  -rss_limit_mb=4096 -max_len=16384 -print_final_stats=1 -dict=tests/fuzz/scene.dict \
  -artifact_prefix="$work/findings/" "$work/corpus" > "$log" 2>&1 || status=$?
executed=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
echo "fuzz: ${executed:-0} executions, ${rate:-0} per second, exit $status; log $log"
if [ "$status" -ne 0 ] || [ -n "$(ls -A "$work/findings")" ]; then
  grep -E "ERROR|SUMMARY|runtime error|Test unit written" "$log" | head -20 || true
  echo "fuzz: FAIL: a finding (reproduce: build/sanitize/bin/noether_fuzz_scene FILE)"; ls "$work/findings"
  exit 1
fi
[ "${executed:-0}" -ge "$runs" ] || { echo "fuzz: FAIL: only ${executed:-0} of $runs executions in ${seconds} s"; exit 1; }
