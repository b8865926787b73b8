"""kill_at_every_write.py NOETHER SOURCE_DIR WORK_DIR [STRIDE]: a run killed with SIGKILL just
before any one of its writes to the file leaves the output path holding either the file that was
there before, untouched, or a file that opens whose first /frames_complete frames are complete
(killed_file.py; docs/reliability.md, "Kills").

The run (the dumbbells, a frame every step, 1,001 frames) is traced once to count its writes
(pwrite64: HDF5's and the superblock's), then repeated once per write, with strace injecting
SIGKILL in place of write k: every window of a random kill (sigkill.py) is visited, including
those inside HDF5's flush and close that random kills hit about once in a thousand.
STRIDE > 1 kills at every STRIDE-th write (the sanitizer build). Exits 77 (skipped) where
strace cannot trace (no ptrace permission).
"""
import os
import signal
import subprocess
import sys

import h5py

import killed_file

noether, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
stride = int(sys.argv[4]) if len(sys.argv) > 4 else 1
os.makedirs(work, exist_ok=True)
os.chdir(work)
h = 0.0002  # the scene's step: a frame every step
args = [noether, "run", os.path.join(src, "examples", "dumbbells.yaml"), "--no-progress", "--force",
        "-o", "run.h5", "--set", "run.t_end=0.2", "--set", f"run.output_every={h}"]
env = dict(os.environ, HDF5_USE_FILE_LOCKING="FALSE")
# LeakSanitizer cannot run under ptrace (the sanitizer build): the traced runs skip it.
env["ASAN_OPTIONS"] = ":".join(filter(None, [os.environ.get("ASAN_OPTIONS"), "detect_leaks=0"]))

probe = subprocess.run(["strace", "-f", "-o", "/dev/null", "true"], capture_output=True, text=True) \
    if any(os.access(os.path.join(d, "strace"), os.X_OK) for d in os.environ["PATH"].split(":")) else None
if probe is None or probe.returncode != 0:
    print("kill_at_every_write: SKIPPED: strace cannot trace here"
          + (f" ({probe.stderr.strip()})" if probe is not None else " (not installed)"))
    sys.exit(77)


def clean():
    for name in os.listdir("."):
        os.remove(name)


clean()
subprocess.run(args, check=True, stdout=subprocess.DEVNULL, env=env)
with h5py.File("run.h5", "r", locking=False) as f:
    E0 = float(f["observables/energy/value"][0])
    frames_full = f["particles/bodies/position/time"].shape[0]
with open("run.h5", "rb") as f:
    previous = f.read()
trace = subprocess.run(["strace", "-f", "-qq", "-o", "trace.txt", "-e", "trace=pwrite64"] + args,
                       check=True, stdout=subprocess.DEVNULL, env=env)
with open("trace.txt") as f:
    writes = sum(1 for line in f if "pwrite64(" in line)
os.remove("trace.txt")
assert writes > 100, f"only {writes} writes traced"

outcomes = {"previous file": 0, "killed mid-run": 0, "every frame complete": 0}
failures = []
for k in range(1, writes + 1, stride):
    with open("run.h5", "wb") as f:  # the previous output, which --force may replace
        f.write(previous)
    run = subprocess.run(["strace", "-f", "-qq", "-o", "/dev/null", "-e", "trace=pwrite64",
                          "-e", f"inject=pwrite64:signal=KILL:when={k}"] + args,
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    killed = run.returncode in (-signal.SIGKILL, 128 + signal.SIGKILL)
    with open("run.h5", "rb") as f:
        if f.read() == previous and killed:
            outcomes["previous file"] += 1
            continue
    try:
        length, n = killed_file.check("run.h5", h, E0, frames_full)
        outcomes["every frame complete" if n == frames_full else "killed mid-run"] += 1
    except Exception as e:  # noqa: BLE001 - any failure to read is the failure under test
        failures.append(f"killed at write {k} of {writes}: {type(e).__name__}: {e}")
    for name in os.listdir("."):
        if ".partial-" in name:  # killed while the file was being created: the path untouched
            os.remove(name)

print(f"kill_at_every_write: {len(range(1, writes + 1, stride))} kills, one at each "
      f"{'' if stride == 1 else f'{stride}th '}of the run's {writes} writes: {outcomes}")
for failure in failures:
    print(f"kill_at_every_write: FAIL: {failure}")
sys.exit(1 if failures else 0)
