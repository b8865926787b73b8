"""resume_legacy.py NOETHER SOURCE_DIR WORK_DIR: files from before /observables/force_balance
was checkpointed (/checkpoint/checksum with 9 columns), the recorded particles' positions were
(10 columns) or the tangent and the run features' fields were (11 columns; now 14) are still continued — bit for bit the uninterrupted run — unless they hold a
forces' balance that no checksum covers, which is refused by name with the file unchanged
(docs/user-guide.md, "Continuing a run")."""
import hashlib
import os
import subprocess
import sys

import h5py
import numpy as np

noether, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
os.chdir(work)
scene = os.path.join(src, "examples", "dumbbells.yaml")
TIDES = "forces=[{plugin: tides, body: beta, k2: 0.3, time_lag: 0.0001, radius: 0.25}]"
failures = []


def run(*args):
    return subprocess.run([noether, *args, "--no-progress"], capture_output=True, text=True)


COLUMNS = 14  # /checkpoint/checksum's columns now


def as_legacy(path, columns):
    """Rewrites /checkpoint/checksum with its first `columns`, as an older noether wrote it."""
    with h5py.File(path, "r+", locking=False) as f:
        sums = f["checkpoint/checksum"]
        assert sums.shape[1] == COLUMNS, sums.shape
        kept, attrs = sums[:, :columns], dict(sums.attrs)
        del f["checkpoint/checksum"]
        new = f.create_dataset("checkpoint/checksum", data=kept, maxshape=(None, columns), chunks=(256, columns))
        for k, v in attrs.items():
            new.attrs[k] = v


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


for label, more, columns in [("plain", [], 9), ("plain", [], 10), ("plain", [], 11), ("tides", ["--set", TIDES], 9)]:
    full, part = f"legacy-{label}-full.h5", f"legacy-{label}-part.h5"
    for name in (full, part):
        if os.path.exists(name):
            os.remove(name)
    if run("run", scene, "-o", full, "--set", "run.t_end=4", *more).returncode != 0:
        failures.append(f"{label}: the uninterrupted run failed")
        continue
    if run("run", scene, "-o", part, "--set", "run.t_end=2", *more).returncode != 0:
        failures.append(f"{label}: the first half failed")
        continue
    as_legacy(part, columns)
    before = digest(part)
    resumed = run("run", "--resume", part, "--t-end", "4")
    if label == "plain":
        if resumed.returncode != 0:
            failures.append(f"plain: a {columns}-column file was not continued: {resumed.stderr.strip()}")
            continue
        with h5py.File(full, "r") as a, h5py.File(part, "r") as b:
            for key in ["particles/bodies/position/value", "checkpoint/linear_momentum", "checkpoint/attitude"]:
                if a[key][()].tobytes() != b[key][()].tobytes():
                    failures.append(f"plain: {key} differs from the uninterrupted run")
            if b["checkpoint/checksum"].shape[1] != COLUMNS:
                failures.append(f"plain: the continued file's checksums are not {COLUMNS} columns")
        print(f"plain: a {columns}-column file continued, bit for bit the uninterrupted run")
    else:
        message = resumed.stderr.strip()
        if resumed.returncode == 0 or "older noether" not in message or "force_balance" not in message:
            failures.append(f"tides: a 9-column file with a forces' balance was not refused by name "
                            f"(exit {resumed.returncode}): {message}")
        if digest(part) != before:
            failures.append("tides: the refused file changed")
        print(f"tides: refused, exit {resumed.returncode}: {message}")

for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
