#!/usr/bin/env bash
# output_safety.sh NOETHER SOURCE_DIR WORK_DIR PYTHON: a user's output is never lost
# (docs/user-guide.md, "Output files"). Checks, each of which fails on a writer that truncates
# first: an existing file is refused without --force and left unchanged; a symbolic link and the
# scene itself are refused even with --force; a second run on the path another run is writing is
# refused and the first run's file survives; SIGTERM stops a run after a complete step with
# exit 143, the summary printed and every series of the file of equal length, ending at the
# reported time.
set -u
noether=$1; src=$2; work=$3; py=$4
fail() { echo "output_safety: FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
scene=$src/examples/dumbbells.yaml
cp "$scene" scene.yaml

# 1. An existing file: refused, byte for byte unchanged.
echo "precious data" > existing.h5
out=$("$noether" run scene.yaml --no-progress -o existing.h5 2>&1); rc=$?
[ $rc -eq 2 ] || fail "existing file: exit $rc, expected 2"
grep -q "exists; noether does not overwrite output unless asked: pass --force" <<<"$out" || fail "existing: $out"
[ "$(cat existing.h5)" = "precious data" ] || fail "the existing file was modified"

# 2. A symbolic link: refused even with --force; its target untouched.
ln -s existing.h5 link.h5
out=$("$noether" run scene.yaml --no-progress --force -o link.h5 2>&1); rc=$?
[ $rc -eq 2 ] || fail "symlink: exit $rc, expected 2"
grep -q "is a symbolic link" <<<"$out" || fail "symlink: $out"
[ "$(cat existing.h5)" = "precious data" ] || fail "the link's target was modified"

# 3. The scene itself: refused even with --force.
out=$("$noether" run scene.yaml --no-progress --force -o scene.yaml 2>&1); rc=$?
[ $rc -eq 2 ] || fail "scene as output: exit $rc, expected 2"
grep -q "is the run's input" <<<"$out" || fail "scene as output: $out"
cmp -s scene.yaml "$scene" || fail "the scene was modified"

# 4. Two runs on one path: the second is refused while the first writes; then SIGTERM.
"$noether" run scene.yaml --no-progress --set run.t_end=1000 --set run.output_every=0.01 -o run.h5 \
  > first.out 2> first.err &
first=$!
for _ in $(seq 100); do [ -s run.h5 ] && break; sleep 0.05; done
sleep 0.5
out=$("$noether" run scene.yaml --no-progress --force -o run.h5 2>&1); rc=$?
[ $rc -eq 2 ] || fail "second run: exit $rc, expected 2 ($out)"
grep -q "another process is writing" <<<"$out" || fail "second run: $out"
kill -TERM $first
wait $first; rc=$?
[ $rc -eq 143 ] || fail "SIGTERM: exit $rc, expected 143: $(cat first.err)"
grep -q "max |E - E0|" first.out || fail "SIGTERM: no summary printed: $(cat first.out)"
grep -q "SIGTERM: stopped at t = " first.err || fail "SIGTERM: $(cat first.err)"
"$py" - run.h5 <<'EOF' || fail "the interrupted file is not complete"
import sys, h5py
with h5py.File(sys.argv[1], "r") as f:
    lengths = {}
    def visit(name, obj):
        if isinstance(obj, h5py.Dataset) and name.rsplit("/", 1)[-1] in ("value", "step", "time"):
            lengths[name] = obj.shape[0]
    f.visititems(visit)
    assert len(set(lengths.values())) == 1, lengths
    outcome = f["work"].attrs["outcome"]
    outcome = outcome.decode() if isinstance(outcome, bytes) else outcome
    t = f["particles/bodies/position/time"][-1]
    print(f"interrupted file: {len(lengths)} series of {lengths.popitem()[1]} frames, last t = {t}; {outcome}")
    assert 0 < t < 1000 and outcome.startswith("stopped: interrupted by signal 15"), outcome
EOF
echo "output_safety: all checks passed"
