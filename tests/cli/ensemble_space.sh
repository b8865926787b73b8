#!/usr/bin/env bash
# ensemble_space.sh NOETHER SOURCE_DIR WORK_DIR: an ensemble file is allocated whole when it is
# created (one row per sample). One that cannot fit is refused before anything is written, with
# the size it needs, and leaves no file behind (a 10^9-point grid used to write 10 GB of hidden
# file and then crash at exit when the disk filled).
set -u
noether=$1; src=$2; work=$3
fail() { echo "ensemble_space: FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
scene=$src/examples/dumbbells.yaml
# Larger than any disk: refused from the free space, at once.
"$noether" ensemble "$scene" --vary 'G=grid(0.1,0.3,1e6)' --vary 'bodies.alpha.mass=grid(1,2,1e6)' --set run.t_end=0.01 -o e.h5 > out.txt 2>&1; rc=$?
[ "$rc" -eq 2 ] || fail "exit $rc: $(cat out.txt)"
grep -Eq "noether: the ensemble file for 1000000000000 samples needs 1.05e\+06 GB \(1050 bytes per sample, allocated when it is created\); \. has [0-9.e+]+ GB free: use fewer samples" out.txt ||
  fail "$(cat out.txt)"
# Larger than a file-size limit (20 MB here; 104 MB needed): the reservation fails cleanly.
bash -c "ulimit -f 20000; trap '' XFSZ; exec '$noether' ensemble '$scene' --vary 'G=uniform(0.1,0.3)' --samples 100000 --set run.t_end=0.01 -o e.h5" > out.txt 2>&1; rc=$?
[ "$rc" -eq 2 ] || fail "file-size limit: exit $rc: $(cat out.txt)"
grep -q "noether: cannot reserve 104200000 bytes for e.h5: File too large" out.txt || fail "$(cat out.txt)"
leftover=$(ls -A)
[ "$leftover" = out.txt ] || fail "files left behind: $leftover"
# Within the limit: the same ensemble at 100 samples runs, and its file is trimmed to its data.
bash -c "ulimit -f 20000; trap '' XFSZ; exec '$noether' ensemble '$scene' --vary 'G=uniform(0.1,0.3)' --samples 100 --set run.t_end=0.01 -o e.h5" > out.txt 2>&1 ||
  fail "100 samples: $(cat out.txt)"
grep -q "outcomes *100 completed" out.txt || fail "$(cat out.txt)"
echo "ensemble_space: refused by free space and by a file-size limit, nothing left behind; 100 samples ran"
