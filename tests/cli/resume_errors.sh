#!/usr/bin/env bash
# resume_errors.sh NOETHER SOURCE_DIR WORK_DIR: what `noether run --resume` refuses, with a message
# a user can act on, and what it does with a run that finished (docs/user-guide.md, "Continuing a run").
set -u
noether=$1; src=$2; work=$3
mkdir -p "$work" && cd "$work" && rm -f ./*.h5
expect=$src/tests/cli/expect.sh
fail=0
check() { bash "$expect" "$@" >/dev/null || { echo "FAILED: ${*:3}"; bash "$expect" "$@" | tail -3; fail=1; }; }

check 2 "give a scene, or --resume" "$noether" run
check 2 "give a scene, or --resume FILE.h5 \(not both\)" "$noether" run "$src/examples/dumbbells.yaml" --resume x.h5
check 2 "missing.h5: no such file" "$noether" run --resume missing.h5
check 2 "-o, --set, --stm, --chaos, --sensitivity and --force do not apply" "$noether" run --resume x.h5 --set run.t_end=3
check 2 "--t-end goes with --resume" "$noether" run "$src/examples/dumbbells.yaml" --t-end 3
echo "not hdf5" > text.h5
check 2 "text.h5 is not an HDF5 file" "$noether" run --resume text.h5

# A finished run: refused without --t-end, extended with one (the summary then covers 0..4).
"$noether" run "$src/examples/dumbbells.yaml" --no-progress --set run.t_end=2 -o done.h5 >/dev/null || fail=1
check 2 "already at t = 2, its t_end; give a later --t-end" "$noether" run --resume done.h5 --no-progress
check 2 "its t_end is not later" "$noether" run --resume done.h5 --no-progress --t-end 1
check 0 "resumed +done.h5 from t = 2 .*output frames +401 " "$noether" run --resume done.h5 --no-progress --t-end 4
# The extended file equals a run to t = 4 in one go.
"$noether" run "$src/examples/dumbbells.yaml" --no-progress --set run.t_end=4 -o whole.h5 >/dev/null || fail=1
/usr/bin/python3 - <<'PY' || fail=1
import h5py, numpy as np, sys
a, b = h5py.File("whole.h5", "r"), h5py.File("done.h5", "r")
for k in ["particles/bodies/position/value", "checkpoint/attitude", "observables/energy/value"]:
    if a[k][()].tobytes() != b[k][()].tobytes():
        sys.exit(f"FAILED: {k} of the extended run differs from the run to t = 4")
if float(b["parameters"].attrs["t_end"]) != 4.0 or "run.t_end=4" not in b["parameters"].attrs["overrides"]:
    sys.exit("FAILED: the extended file does not record its new t_end")
PY

# A file from a noether before checksums (made here by deleting them) continues, with a warning,
# to the same file as the checksummed one; the continued file has checksums again.
"$noether" run "$src/examples/dumbbells.yaml" --no-progress --set run.t_end=1 -o new.h5 >/dev/null || fail=1
cp new.h5 old.h5
/usr/bin/python3 -c '
import h5py
with h5py.File("old.h5", "r+") as f:
    del f["checkpoint/checksum"]
    del f["parameters"].attrs["checksum"]
    del f["work"].attrs["outcome_checksum"]
' || fail=1
check 0 "old.h5 was written by a noether without checksums: its frames are continued unverified" \
  "$noether" run --resume old.h5 --no-progress --t-end 2
"$noether" run --resume new.h5 --no-progress --t-end 2 >/dev/null || fail=1
/usr/bin/python3 - <<'PY' || fail=1
import h5py, sys
a, b = h5py.File("new.h5", "r"), h5py.File("old.h5", "r")
for k in ["particles/bodies/position/value", "checkpoint/attitude", "observables/energy/value", "checkpoint/work"]:
    if a[k][()].tobytes() != b[k][()].tobytes():
        sys.exit(f"FAILED: {k} of the continued old file differs from the checksummed file's")
if "checkpoint/checksum" not in b:
    sys.exit("FAILED: the continued old file has no checksums")
PY

# A run that ended at a collision has nothing to continue.
"$noether" run "$src/examples/collision.yaml" --no-progress -o hit.h5 >/dev/null
check 2 "ended at an event \(collision" "$noether" run --resume hit.h5 --no-progress
exit $fail
