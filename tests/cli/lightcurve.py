"""lightcurve.py NOETHER SOURCE_DIR WORK_DIR: lightcurves from a run (docs/fitting.md, "Lightcurves").

End to end, against what is computed here independently: Dimorphos alone, spinning, against the
closed-form Lommel–Seeliger ellipsoid (Muinonen & Lumme 2015) at the file's own attitudes — the
placement of the surface by the run's quaternions; the pair against the sum of its bodies away
from the mutual events and below it during them; between frames (eq. 29.4 for the attitudes)
against a run that has frames at those times; and what is refused, exit 2, by name.
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
rkf78 = ["--set", "integrator={plugin: rk, method: rkf78, rtol: 1.0e-12, atol: 1.0e-9}"]


def run(output, every, *more):
    subprocess.run([noether, "run", scene, "--no-progress", "--force", "--set", "run.t_end=10800",
                    "--set", f"run.output_every={every}", "-o", output, *rkf78, *more], check=True,
                   stdout=subprocess.DEVNULL)


def observe(*args, check=True):
    return subprocess.run([noether, "observe", *args], capture_output=True, text=True, check=check)


def values(path):
    with open(path) as f:
        lines = [l.strip() for l in f if l.strip() and not l.startswith("#")]
    header = lines[0].split(",")
    cells = [dict(zip(header, l.split(","))) for l in lines[1:]]
    return np.array([float(c["t"]) for c in cells]), np.array([float(c["value"]) for c in cells])


run("coarse.h5", 600)
run("fine.h5", 60)
# Dimorphos passes in front of Didymos near t = 1.5 h seen from there, at 15° phase.
los = np.array([-1.0, -1.0, -0.1])
sun = np.array([[np.cos(0.26), -np.sin(0.26), 0], [np.sin(0.26), np.cos(0.26), 0], [0, 0, 1]]) @ los
views = ["--line-of-sight", ",".join(map(str, los)), "--sunlight", ",".join(map(str, sun))]

# Dimorphos alone against the closed form, at its attitudes as the file records them.
observe("coarse.h5", "--observable", "lightcurve.lommel_seeliger:dimorphos:dimorphos", *views, "--tessellation", "5",
        "-o", "alone.csv", "--force")
t, F = values("alone.csv")
with h5py.File("coarse.h5", "r") as f:
    q = f["particles/bodies/orientation/value"][:, 1]  # (w, x, y, z), body → scene


def rotation(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def lommel_seeliger_ellipsoid(axes, s, o):
    """Muinonen & Lumme (2015): an ellipsoid's disk-integrated brightness in the units of eq. 29.2."""
    c = 1 / np.asarray(axes) ** 2
    Ss, So = np.sqrt(s @ (c * s)), np.sqrt(o @ (c * o))
    cos_a = np.clip(s @ (c * o) / (Ss * So), -1, 1)
    a = np.arccos(cos_a)
    S = np.sqrt(Ss ** 2 + So ** 2 + 2 * Ss * So * cos_a)
    lam = np.arctan2(So * np.sin(a), Ss + So * cos_a)
    bracket = np.cos(a - lam) + np.cos(lam)
    if a > 1e-12:
        bracket -= np.sin(lam) * np.sin(a - lam) * np.log(1 / (np.tan(lam / 2) * np.tan((a - lam) / 2)))
    return np.pi * np.prod(axes) / 2 * Ss * So / S * bracket


s_hat, o_hat = -sun / np.linalg.norm(sun), -los / np.linalg.norm(los)
exact = np.array([lommel_seeliger_ellipsoid([103.16, 79.35, 66.13], rotation(qk).T @ s_hat, rotation(qk).T @ o_hat)
                  for qk in q])
worst = np.max(np.abs(F / exact - 1))
print(f"Dimorphos alone, {len(t)} frames: within {worst:.1e} of the closed-form ellipsoid (1280·4 facets)")
assert worst < 5e-4, worst

# The pair against its two bodies: equal away from the events, below during them.
pair = {}
for spec in ["dimorphos:didymos", "didymos:didymos", "dimorphos:dimorphos"]:
    observe("fine.h5", "--observable", f"lightcurve.lommel_seeliger:{spec}", *views, "--every", "2", "-o", "lc.csv",
            "--force")
    pair[spec] = values("lc.csv")
t = pair["dimorphos:didymos"][0]
both, alone = pair["dimorphos:didymos"][1], pair["didymos:didymos"][1] + pair["dimorphos:dimorphos"][1]
depth = 1 - both / alone
event = depth > 1e-12
assert np.all(depth > -1e-12), depth.min()
assert event.any() and not event.all()
print(f"the pair: equal to the sum of its bodies at {np.sum(~event)} frames, below it at {np.sum(event)} "
      f"(t = {t[event].min() / 3600:.2f} … {t[event].max() / 3600:.2f} h, deepest {depth.max():.3f})")
assert 0.03 < depth.max() < 0.2 and 0.5 * 3600 < t[np.argmax(depth)] < 2.5 * 3600, (depth.max(), t[np.argmax(depth)])

# Between frames: the 600 s run at the 60 s run's frame times, the attitudes by eq. 29.4.
with open("at.csv", "w") as f:
    f.write("t,observable,target,center,value,sigma,los_x,los_y,los_z,sun_x,sun_y,sun_z\n")
    for tk in np.arange(60.0, 10800.0, 420.0):
        f.write(f"{tk},lightcurve.lommel_seeliger,dimorphos,didymos,,," + ",".join(map(str, [*los, *sun])) + "\n")
observe("coarse.h5", "--at", "at.csv", "--sigma", "100", "-o", "between.csv", "--force")
observe("fine.h5", "--at", "at.csv", "-o", "on-frames.csv", "--force")
worst = np.max(np.abs(values("between.csv")[1] / values("on-frames.csv")[1] - 1))
print(f"between frames 600 s apart against frames at those times: within {worst:.1e} relative")
assert worst < 1e-5, worst


def refused(expect, *args):
    p = observe(*args, check=False)
    assert p.returncode == 2 and expect in p.stderr, (args, p.returncode, p.stderr)


refused("needs the sunlight's direction X,Y,Z", "fine.h5", "--observable", "lightcurve.lambert:dimorphos:didymos",
        "--line-of-sight", "1,0,0")
refused("--tessellation must be in [0, 8]", "fine.h5", "--observable", "lightcurve.lambert:dimorphos:didymos",
        *views, "--tessellation", "9")
subprocess.run([noether, "run", scene, "--no-progress", "--force", "--set", "run.t_end=7200", "--set",
                "run.output_every=3600", "-o", "sparse.h5"], check=True, stdout=subprocess.DEVNULL)
refused("'didymos' turns by 2.78", "sparse.h5", "--at", "at.csv")
point = os.path.join(src, "examples", "figure-eight.yaml")
subprocess.run([noether, "run", point, "--no-progress", "--force", "--set", "integrator.step=0.01", "--set",
                "run.t_end=0.1", "--set", "run.output_every=0.1", "-o", "points.h5"],
               check=True, stdout=subprocess.DEVNULL)
with h5py.File("points.h5", "r") as f:
    a, b = [n.decode() if isinstance(n, bytes) else n for n in f["particles/bodies/name"][:2]]
refused(f"body '{a}' has no surface for a lightcurve", "points.h5", "--observable",
        f"lightcurve.lambert:{a}:{b}", *views)
fit = subprocess.run([noether, "fit", scene, "--observations", "between.csv", "--free", "bodies.dimorphos.density"],
                     capture_output=True, text=True)
assert fit.returncode == 2 and "lightcurve.lommel_seeliger cannot be fitted yet" in fit.stderr, fit.stderr
print("refused by name: no sunlight, a tessellation out of range, frames too sparse for the spin, a body without a "
      "surface, a lightcurve in a fit")
