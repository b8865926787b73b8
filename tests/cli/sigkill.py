"""sigkill.py NOETHER SOURCE_DIR WORK_DIR [KILLS]: a run killed with SIGKILL at any moment leaves
its output path holding either the file that was there before, untouched, or a file that opens
whose first /frames_complete frames are complete (killed_file.py; docs/user-guide.md, "Output
files"). kill_at_every_write.py kills the same run at each of its writes in turn.

Each run writes a frame every step (the dumbbells, 50,000 frames in about 0.15 s) over an
existing file with --force, and is killed at a random moment between its start and a little
after its expected end, so kills land while the file is created, while blocks are flushed and
while the run finishes. Fails on a writer that commits frames before their data (a series shorter
than /frames_complete) or truncates before the new file is ready.
"""
import os
import random
import signal
import subprocess
import sys
import time

import h5py

import killed_file

noether, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
kills = int(sys.argv[4]) if len(sys.argv) > 4 else 100
os.makedirs(work, exist_ok=True)
os.chdir(work)
scene = os.path.join(src, "examples", "dumbbells.yaml")
h = 0.0002  # the scene's step: a frame every step
args = [noether, "run", scene, "--no-progress", "--force", "-o", "run.h5",
        "--set", "run.t_end=10", "--set", f"run.output_every={h}"]
env = dict(os.environ, HDF5_USE_FILE_LOCKING="FALSE")

# How long a whole run takes here, to spread the kills over it: the median of three runs (the
# first one on a fresh machine pays for loading the program and its plugins from disk, and
# once inflated the duration so much that most kills landed after the end).
for name in os.listdir("."):
    os.remove(name)
durations = []
for _ in range(3):
    t = time.monotonic()
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL, env=env)
    durations.append(time.monotonic() - t)
duration = sorted(durations)[1]
with h5py.File("run.h5", "r", locking=False) as f:
    E0 = float(f["observables/energy/value"][0])
    frames_full = f["particles/bodies/position/time"].shape[0]
with open("run.h5", "rb") as f:
    previous = f.read()

rng = random.Random(18)
outcomes = {"previous file": 0, "killed mid-run": 0, "finished": 0}
partial_left = 0
# At least `kills` kills, and more (up to 3×) until a fifth of them landed mid-run: on a loaded
# machine the runs' durations vary, and a test of kills mid-run needs kills mid-run.
k = -1
while k + 1 < kills or (outcomes["killed mid-run"] < kills // 5 and k + 1 < 3 * kills):
    k += 1
    with open("run.h5", "wb") as f:  # the previous output, which --force may replace
        f.write(previous)
    run = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    time.sleep(rng.uniform(0.0, 1.2 * duration))
    run.send_signal(signal.SIGKILL)
    run.wait()
    with open("run.h5", "rb") as f:
        if f.read() == previous and run.returncode == -signal.SIGKILL:
            outcomes["previous file"] += 1
            continue
    try:
        length, n = killed_file.check("run.h5", h, E0, frames_full)
    except Exception as e:  # noqa: BLE001 - any failure to read is the failure under test
        print(f"sigkill: FAIL after kill {k}: {type(e).__name__}: {e}")
        sys.exit(1)
    outcomes["finished" if n == frames_full else "killed mid-run"] += 1
    for name in os.listdir("."):
        if ".partial-" in name:  # a kill while the file was being created: the path untouched
            partial_left += 1
            os.remove(name)

print(f"sigkill: {k + 1} kills over runs of {duration:.2f} s (three runs: "
      f"{', '.join(f'{d:.2f}' for d in durations)} s): {outcomes}; "
      f"hidden partial files left by kills during creation: {partial_left}")
if outcomes["killed mid-run"] < kills // 5:
    print(f"sigkill: FAIL: only {outcomes['killed mid-run']} kills landed mid-run (wanted {kills // 5})")
    sys.exit(1)
