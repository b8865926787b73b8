"""corrupt_resume.py NOETHER SOURCE_DIR WORK_DIR [CASES]: `noether run --resume` on damaged output
files either refuses them by name, leaving them unchanged, or continues them to the same result
as the undamaged file — never to a different result (docs/reliability.md, "Checksums").

Two files to continue: the dumbbells under the LGVI run to t = 2 and extended to t = 3 (a run
that ended: /work written, series of their final length), and the same under the relative
Lagrangian LGVI killed with SIGKILL partway (no /work, series preallocated past
/frames_complete, /checkpoint/integrator present). Each is continued once undamaged: the
reference. Then CASES copies of each (seeded) are damaged anywhere in the file, as disks and
copies damage files: 1 to 8 random bytes flipped, or a 4 KiB block zeroed (at a random offset or
a 4 KiB-aligned one), and continued. Each outcome must be one of:
  * exit 0 and every series of the continued file bitwise the reference's (the damage was in
    bytes the continuation does not read, or in derived series it writes again);
  * exit 2, a message that names the file, the file byte for byte as it was, and no hidden
    .partial file left beside it.
Anything else fails: a different result, another exit code, a crash, or a continuation that
takes over 60 s (a hang). The counts are printed by kind of refusal.
"""
import hashlib
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import time
from collections import Counter

import h5py
import numpy as np

noether, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
cases = int(sys.argv[4]) if len(sys.argv) > 4 else 120
os.makedirs(work, exist_ok=True)
os.chdir(work)
for name in os.listdir("."):
    os.remove(name)
scene = os.path.join(src, "examples", "dumbbells.yaml")
rng = random.Random(20261124)

COMPARED = ["particles/bodies/position/time", "particles/bodies/position/value", "particles/bodies/position/step",
            "particles/bodies/velocity/value", "particles/bodies/orientation/value",
            "particles/bodies/angular_momentum/value", "checkpoint/linear_momentum", "checkpoint/attitude",
            "checkpoint/work", "observables/energy/value",  # not the checksums: they cover wall times
            "observables/potential_energy/value", "observables/linear_momentum/value",
            "observables/angular_momentum/value", "observables/orthogonality_error/value", "frames_complete"]


def run(args, timeout=60):
    p = subprocess.Popen([noether] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        out, err = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        p.kill()
        p.communicate()
        return None, "", "hang"
    return p.returncode, out, err


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def contents(path):
    with h5py.File(path, "r", locking=False) as f:
        return {k: f[k][()].tobytes() for k in COMPARED if k in f}, f["work"].attrs["outcome"]


def reason_of(err, damaged):
    """The kind of a refusal, for the counts."""
    checksum = re.search(r"frame [0-9]+ of (/[A-Za-z_/]+) does not match its checksum", err)
    if checksum:
        return "checksum of " + checksum.group(1)
    for phrase, kind in [("HDF5 crashed", "HDF5 crashed reading it (in the child)"),
                         ("did not end within", "HDF5 looped reading it (in the child)"),
                         ("does not match its checksum", "checksum of a text"),
                         ("do not read", "HDF5 found the data unreadable"),
                         ("does not read", "HDF5 found a group unreadable"),
                         ("is missing or does not open", "HDF5 found a dataset unreadable"),
                         ("not an HDF5 file", "HDF5 superblock"), ("is damaged", "damaged (other)")]:
        if phrase in err:
            return kind
    return re.sub(r".*" + re.escape(damaged) + r":? ?", "", err.strip().splitlines()[-1])[:70]


# The two files to continue.
sets = ["--no-progress", "--set", "run.output_every=0.01"]
code, _, err = run(["run", scene, "-o", "ended.h5", "--set", "run.t_end=2"] + sets)
assert code == 0, err
relative = ["--set", "integrator={plugin: lgvi, step: 0.0002, frame: relative, form: lagrangian}"]
p = subprocess.Popen([noether, "run", scene, "-o", "killed.h5", "--set", "run.t_end=300"] + sets + relative,
                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
deadline = time.monotonic() + 120
while time.monotonic() < deadline:
    time.sleep(0.05)
    try:
        with h5py.File("killed.h5", "r", locking=False) as f:
            if int(f["frames_complete"][()]) >= 300:
                break
    except (OSError, KeyError):
        pass
p.send_signal(signal.SIGKILL)
p.wait()
bases = {"ended.h5": "3", "killed.h5": None}  # the t_end to continue to
with h5py.File("killed.h5", "r", locking=False) as f:
    n = int(f["frames_complete"][()])
    bases["killed.h5"] = repr(float(f["particles/bodies/position/time"][n - 1]) + 1.0)

failures, outcomes = [], Counter()
for base, t_end in bases.items():
    reference = "reference-" + base
    shutil.copy(base, reference)
    code, _, err = run(["run", "--resume", reference, "--t-end", t_end, "--no-progress"])
    assert code == 0, f"{base}: the undamaged continuation failed: {err}"
    expected = contents(reference)
    size = os.path.getsize(base)
    for case in range(cases):
        damaged = f"case-{case}-{base}"
        shutil.copy(base, damaged)
        with open(damaged, "r+b") as f:
            data = bytearray(f.read())
            kind = rng.choice(["bytes", "block", "aligned block"])
            if kind == "bytes":
                for _ in range(rng.randint(1, 8)):
                    data[rng.randrange(size)] ^= 1 << rng.randrange(8)
            else:
                start = rng.randrange(size) if kind == "block" else 4096 * rng.randrange(size // 4096 + 1)
                data[start:start + 4096] = bytes(len(data[start:start + 4096]))
            f.seek(0)
            f.write(data)
        before = digest(damaged)
        code, _, err = run(["run", "--resume", damaged, "--t-end", t_end, "--no-progress"])
        what = f"{base} case {case} ({kind})"
        leftovers = [x for x in os.listdir(".") if x.startswith("." + damaged + ".partial")]
        if leftovers:
            failures.append(f"{what}: left {leftovers}")
            for x in leftovers:
                os.remove(x)
        if code == 0:
            try:
                got = contents(damaged)
            except Exception as e:  # noqa: BLE001 - any failure to read the result is a finding
                failures.append(f"{what}: continued (exit 0) to a file that does not read: {e}")
                continue
            differ = [k for k in COMPARED if got[0].get(k) != expected[0].get(k)] + (
                ["outcome"] if got[1] != expected[1] else [])
            if differ:
                failures.append(f"{what}: SILENTLY DIFFERENT from the undamaged continuation: {differ}")
            else:
                outcomes["continued, identical"] += 1
        elif code == 2:
            if digest(damaged) != before:
                failures.append(f"{what}: refused, but the file was changed: {err.strip()}")
            elif damaged not in err:
                failures.append(f"{what}: refused without naming the file: {err.strip()}")
            else:
                outcomes["refused: " + reason_of(err, damaged)] += 1
        else:
            failures.append(f"{what}: exit {code}: {err.strip()[-300:]}")
        os.remove(damaged)

total = sum(outcomes.values())
print(f"{2 * cases} damaged files: {total} handled")
for k, v in sorted(outcomes.items(), key=lambda kv: -kv[1]):
    print(f"  {v:4d}  {k}")
for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
