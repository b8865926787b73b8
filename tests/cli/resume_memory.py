"""resume_memory.py NOETHER SOURCE_DIR WORK_DIR: the memory `noether run --resume` needs does not
grow with the number of frames recorded (docs/reliability.md, "Checksums").

The dumbbells writing a frame every step, to 2 x 10^4 and to 2 x 10^5 frames, each continued by
one more step's worth of frames. A continuation that held every recorded frame's state in memory
(352 bytes a frame for two rigid bodies: t, x, gamma, R, Pi, U, work, wall time) would peak
~60 MiB higher on the larger file; the peak resident sets (wait4's ru_maxrss) must differ by less
than 8 MiB.
"""
import os
import subprocess
import sys

noether, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
os.chdir(work)
scene = os.path.join(src, "examples", "dumbbells.yaml")
h = 0.0002  # the scene's step


def peak_rss_mib(args):
    p = subprocess.Popen([noether] + args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(p.pid, 0)
    err = p.stderr.read().decode()
    assert os.waitstatus_to_exitcode(status) == 0, err
    return usage.ru_maxrss / 1024.0


peaks = {}
for frames in (20000, 200000):
    path = f"frames-{frames}.h5"
    if os.path.exists(path):
        os.remove(path)
    t_end = frames * h
    subprocess.run([noether, "run", scene, "-o", path, "--no-progress", "--set", f"run.t_end={t_end!r}",
                    "--set", f"run.output_every={h!r}"], check=True, stdout=subprocess.DEVNULL)
    peaks[frames] = peak_rss_mib(["run", "--resume", path, "--t-end", repr(t_end + 10 * h), "--no-progress"])
    os.remove(path)
    print(f"--resume of {frames} frames: peak RSS {peaks[frames]:.1f} MiB")
growth = peaks[200000] - peaks[20000]
print(f"growth over 180,000 more frames: {growth:.1f} MiB (holding them would take ~60 MiB)")
sys.exit(0 if growth < 8.0 else 1)
