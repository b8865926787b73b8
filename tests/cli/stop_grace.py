"""stop_grace.py NOETHER SOURCE_DIR WORK_DIR: SIGTERM ends a run even when the run cannot stop
cleanly — here a potential plugin whose evaluation never returns (the `hangs` fixture, stuck
from t = 0.05 on), so the stepping loop never reads the stop flag. 20 s after the signal SIGALRM
ends the process with 143 and a message; the output opens, as its last flush left it
(docs/reliability.md, "A run's output"). Run with NOETHER_PLUGIN_PATH naming the fixtures.
"""
import os
import signal
import subprocess
import sys
import time

import h5py

noether, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
os.chdir(work)
if os.path.exists("hang.h5"):
    os.remove("hang.h5")
p = subprocess.Popen([noether, "run", os.path.join(src, "examples", "dumbbells.yaml"), "--no-progress", "-o", "hang.h5",
                      "--set", "potential.plugin=hangs", "--set", "run.output_every=0.01"],
                     stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
time.sleep(2.0)  # well past t = 0.05: stuck inside the plugin
assert p.poll() is None, f"the run ended by itself (exit {p.returncode}): {p.stderr.read()}"
start = time.monotonic()
p.send_signal(signal.SIGTERM)
try:
    err = p.communicate(timeout=60)[1]
except subprocess.TimeoutExpired:
    p.kill()
    sys.exit("FAIL: the run did not end within 60 s of SIGTERM")
waited = time.monotonic() - start
failures = []
if p.returncode != 143 or "did not stop within 20 s" not in err:
    failures.append(f"exit {p.returncode}, expected 143 and the grace message: {err.strip()}")
if not 19.0 <= waited <= 40.0:
    failures.append(f"ended {waited:.1f} s after the signal, expected ~20 s")
with h5py.File("hang.h5", "r", locking=False) as f:  # as its last flush left it: opens, consistent
    n, length = int(f["frames_complete"][()]), f["particles/bodies/position/time"].shape[0]
    if not 0 <= n <= length:
        failures.append(f"/frames_complete {n} with series of {length} frames")
print(f"SIGTERM into a hung evaluation: exit {p.returncode} after {waited:.1f} s")
for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
