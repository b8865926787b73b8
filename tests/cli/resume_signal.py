"""resume_signal.py NOETHER SOURCE_DIR WORK_DIR: SIGTERM or SIGINT while `noether run --resume` reads
its file back ends the continuation at once (exit 143 / 130) and leaves the file byte for byte as it
was (docs/reliability.md, "Checksums").

The dumbbells writing a frame every step to 2 x 10^5 frames (250 MB). The continuation first reads
the whole file in a child process (io/read_probe.hpp); the signal is sent as soon as that child
exists, so it lands while the file is read back.
"""
import hashlib
import os
import signal
import subprocess
import sys
import time

noether, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
os.chdir(work)
scene = os.path.join(src, "examples", "dumbbells.yaml")
h, frames = 0.0002, 200000
path = "run.h5"
if os.path.exists(path):
    os.remove(path)
subprocess.run([noether, "run", scene, "-o", path, "--no-progress", "--set", f"run.t_end={frames * h!r}",
                "--set", f"run.output_every={h!r}"], check=True, stdout=subprocess.DEVNULL)


def digest():
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def children(pid):
    try:
        with open(f"/proc/{pid}/task/{pid}/children") as f:
            return f.read().split()
    except OSError:
        return []


before = digest()
failures = []
for sig, code in [(signal.SIGTERM, 143), (signal.SIGINT, 130)]:
    p = subprocess.Popen([noether, "run", "--resume", path, "--t-end", repr(frames * h + 1.0), "--no-progress"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not children(p.pid) and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.001)
    if p.poll() is not None:
        failures.append(f"{sig.name}: the continuation ended before it read the file back in a child "
                        f"(exit {p.returncode})")
        continue
    p.send_signal(sig)
    try:
        err = p.communicate(timeout=30)[1]
    except subprocess.TimeoutExpired:
        p.kill()
        failures.append(f"{sig.name}: the continuation did not end within 30 s of the signal")
        continue
    if p.returncode != code or "being read back" not in err:
        failures.append(f"{sig.name}: exit {p.returncode} (expected {code}): {err.strip()}")
    if digest() != before:
        failures.append(f"{sig.name}: the file changed")
    left = [x for x in os.listdir(".") if ".partial" in x]
    if left:
        failures.append(f"{sig.name}: left {left}")
    print(f"{sig.name} while reading back: exit {p.returncode}, file unchanged: {digest() == before}")
os.remove(path)
for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
