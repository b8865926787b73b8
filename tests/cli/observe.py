"""observe.py NOETHER SOURCE_DIR WORK_DIR: `noether observe` (docs/fitting.md, "Observables").

Every observable at every frame against the same quantity computed here from the file's
positions and velocities with numpy (an independent formulation); `--at` between frames against a
run that has frames at those times (the Hermite interpolant's error); `--noise` against its
sigma (the normalised residuals' mean and spread); and what is refused, exit 2, by name.
"""
import os
import subprocess
import sys

import h5py
import numpy as np

noether, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
os.chdir(work)
scene = os.path.join(src, "examples", "didymos.yaml")


def run(output, every, *more):
    subprocess.run([noether, "run", scene, "--no-progress", "--force", "--set", "run.t_end=21600",
                    "--set", f"run.output_every={every}", "-o", output, *more], check=True, stdout=subprocess.DEVNULL)


rkf78 = ["--set", "integrator={plugin: rk, method: rkf78, rtol: 1.0e-12, atol: 1.0e-9}"]


def observe(*args, check=True):
    return subprocess.run([noether, "observe", *args], capture_output=True, text=True, check=check)


def rows(path):
    """An observation file as (t, observable, value, sigma) tuples."""
    with open(path) as f:
        lines = [l.strip() for l in f if l.strip() and not l.startswith("#")]
    header = lines[0].split(",")
    cells = [dict(zip(header, l.split(","))) for l in lines[1:]]
    return [(float(c["t"]), c["observable"], float(c["value"]), float(c["sigma"]) if c["sigma"] else 0.0)
            for c in cells]


run("coarse.h5", 600)
run("fine.h5", 30)
run("coarse-rk.h5", 600, *rkf78)
run("medium-rk.h5", 300, *rkf78)
run("fine-rk.h5", 30, *rkf78)
los = np.array([0.3, -0.8, 0.5])
names = ["position.x", "position.y", "position.z", "sky.east", "sky.north", "range", "range_rate"]
observe("coarse.h5", "--observable", *[f"{n}:dimorphos:didymos" for n in names], "--line-of-sight", "0.3,-0.8,0.5",
        "-o", "every.csv", "--force")

# Independent: the file's positions and velocities, the sky plane built from its definition.
with h5py.File("coarse.h5", "r") as f:
    t = f["particles/bodies/position/time"][:]
    x = f["particles/bodies/position/value"][:]
    v = f["particles/bodies/velocity/value"][:]
r, u = x[:, 1] - x[:, 0], v[:, 1] - v[:, 0]
ell = los / np.linalg.norm(los)
north = np.array([0, 0, 1]) - ell[2] * ell
north /= np.linalg.norm(north)
east = np.cross(north, ell)
rho = np.linalg.norm(r, axis=1)
expected = {"position.x": r[:, 0], "position.y": r[:, 1], "position.z": r[:, 2], "sky.east": r @ east,
            "sky.north": r @ north, "range": rho, "range_rate": np.sum(r * u, axis=1) / rho}
got = rows("every.csv")
assert len(got) == len(t) * len(names), (len(got), len(t))
scale = {n: max(1e-300, np.max(np.abs(expected[n]))) for n in names}
worst = {n: 0.0 for n in names}
for k, (tk, name, value, _) in enumerate(got):
    frame = k // len(names)
    assert tk == t[frame] and name == names[k % len(names)], (tk, name)
    worst[name] = max(worst[name], abs(value - expected[name][frame]) / scale[name])
# The file's velocities are rounded from the exact momenta (velocity = γ/m): 1e-13 relative.
assert max(worst.values()) < 1e-12, worst
print("every observable at every frame against numpy: worst relative", f"{max(worst.values()):.1e}")

# Between frames: rows at times the coarse runs do not have (off their grids) against a run's
# frames (30 s) at those times, with rkf78 at rtol 1e-12 (its frames the flow's to ~1e-9 m). The
# cubic Hermite interpolant's error is about r ω⁴ Δ⁴ / 384 on a circular orbit of radius r and
# rate ω: 1.9e-4 m for the mutual orbit (1.2 km, 11.9 h) sampled every Δ = 600 s, and 16 times
# less every 300 s (docs/fitting.md: how often to write frames for a fit).
with open("at.csv", "w") as f:
    f.write("t,observable,target,center,value,sigma\n")
    for tk in np.arange(330.0, 21000.0, 990.0):
        for n in ["position.x", "position.y", "range", "range_rate"]:
            f.write(f"{tk},{n},dimorphos,didymos,,2\n")


def between_frames(coarse, fine):
    observe(coarse, "--at", "at.csv", "-o", "between.csv", "--force")
    observe(fine, "--at", "at.csv", "-o", "on-frames.csv", "--force")
    between, on_frames = rows("between.csv"), rows("on-frames.csv")
    assert all(a[3] == 2 for a in between)
    return (max(abs(a[2] - b[2]) for a, b in zip(between, on_frames) if a[1] != "range_rate"),
            max(abs(a[2] - b[2]) for a, b in zip(between, on_frames) if a[1] == "range_rate"))


bound = 1200 * (2 * np.pi / 42958 * 600) ** 4 / 384
errors = [between_frames(f"{name}-rk.h5", "fine-rk.h5") for name in ["coarse", "medium"]]
print(f"rkf78, between frames 600 s apart: positions within {errors[0][0]:.2e} m (estimate r ω⁴ Δ⁴ / 384: {bound:.2e}), range rate "
      f"{errors[0][1]:.1e} m/s; 300 s apart: {errors[1][0]:.2e} m ({errors[0][0] / errors[1][0]:.1f} times less)")
assert errors[0][0] < 1.25 * bound and 12 < errors[0][0] / errors[1][0] < 20, errors

# Noise: 2 observables × 721 frames of the fine run, each row's residual over its sigma.
observe("fine.h5", "--observable", "position.x:dimorphos:didymos", "range:dimorphos:didymos", "--sigma", "1.5",
        "-o", "clean.csv", "--force")
observe("fine.h5", "--observable", "position.x:dimorphos:didymos", "range:dimorphos:didymos", "--sigma", "1.5",
        "--noise", "--seed", "3", "-o", "noisy.csv", "--force")
z = np.array([(a[2] - b[2]) / a[3] for a, b in zip(rows("noisy.csv"), rows("clean.csv"))])
print(f"noise: {len(z)} rows, mean {z.mean():.3f}, standard deviation {z.std():.3f} (of sigma)")
assert abs(z.mean()) < 4 / np.sqrt(len(z)) and abs(z.std() - 1) < 0.05, (z.mean(), z.std())
again = observe("fine.h5", "--observable", "position.x:dimorphos:didymos", "range:dimorphos:didymos", "--sigma", "1.5",
                "--noise", "--seed", "3").stdout
assert again == open("noisy.csv").read()  # the seed decides

# Refused, exit 2, by name.
def refused(expect, *args):
    p = observe(*args, check=False)
    assert p.returncode == 2 and expect in p.stderr, (args, p.returncode, p.stderr)


with open("late.csv", "w") as f:
    f.write("t,observable,target,center,value,sigma\n0,range,dimorphos,didymos,,1\n30000,range,dimorphos,didymos,,1\n")
refused("late.csv:3: t = 30000 is outside the run (0 … 21600)", "coarse.h5", "--at", "late.csv")
with open("unknown.csv", "w") as f:
    f.write("t,observable,target,center,value,sigma\n0,range,dimorphus,didymos,,1\n")
refused("unknown.csv:2: column 'target': no body 'dimorphus' in the run (its bodies: didymos, dimorphos)",
        "coarse.h5", "--at", "unknown.csv")
with open("sigma.csv", "w") as f:
    f.write("t,observable,target,center,value,sigma\n0,range,dimorphos,didymos,,-1\n")
refused("sigma.csv:2: column 'sigma': must be positive (got -1)", "coarse.h5", "--at", "sigma.csv")
refused("no body 'dimorphus' in the run (did you mean dimorphos?)", "coarse.h5", "--observable", "range:dimorphus:didymos")
refused("needs a line of sight", "coarse.h5", "--observable", "sky.east:dimorphos:didymos")
refused("noise needs a sigma", "coarse.h5", "--observable", "range:dimorphos:didymos", "--noise")
refused("every.csv exists", "coarse.h5", "--observable", "range:dimorphos:didymos", "-o", "every.csv")
refused("no such file", "missing.h5", "--observable", "range:dimorphos:didymos")
print("refused by name: a time outside the run, an unknown body, a non-positive sigma, a missing line of sight")
