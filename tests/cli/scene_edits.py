"""scene_edits.py NOETHER SOURCE_DIR WORK_DIR: editing a scene from the command line, and the
attitudes as Euler angles (docs/user-guide.md, "Overrides" and "Output"; docs/equations.md
eqs. 17.9–17.10).

- `--set 'bodies+={...}'` adds a body (the file has it, on the orbit asked for), `bodies.NAME=~`
  removes one, `KEY=~` deletes a key; a shaped body's `mass` replaces the scene's density (and
  the density follows from the shape's volume), also through `noether ensemble --vary`; wrong
  edits and a copied scene without its shapes are refused with what to do.
- `euler_angles` compose back to the attitudes; a secondary given by Euler angles in the orbit
  frame reads them back at t = 0; a half turn of Dimorphos' ellipsoid (a symmetry of the body)
  leaves its orbit-frame angles unchanged over the run; their yaw is minus the libration angle.
"""
import math
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

noether, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
didymos = os.path.join(src, "examples", "didymos.yaml")
dumbbells = os.path.join(src, "examples", "dumbbells.yaml")


def run(scene, out, *sets, status=0):
    args = [noether, "run", scene, "--no-progress", "--force", "-o", os.path.join(work, out)]
    for s in sets:
        args += ["--set", s]
    p = subprocess.run(args, capture_output=True, text=True)
    assert p.returncode == status, (sets, p.returncode, p.stderr[-800:])
    return p.stdout + p.stderr


def read(out):
    return h5py.File(os.path.join(work, out), "r", locking=False)


# --- editing scenes -------------------------------------------------------------------------
run(didymos, "probe.h5", "run.t_end=3600", "integrator.step=10",
    "bodies+={name: probe, mass: 1, orbit: {around: didymos, a: 600, e: 0}}")
with read("probe.h5") as f:
    names = [n.decode() if isinstance(n, bytes) else n for n in f["particles/bodies/name"][()]]
    assert names == ["didymos", "dimorphos", "probe"], names
    x = f["particles/bodies/position/value"][0]
    r = np.linalg.norm(x[2] - x[0])
    assert abs(r - 600) < 1e-9, r  # the orbit asked for, about didymos
    assert f["particles/bodies/mass"][2] == 1.0

run(didymos, "alone.h5", "run.t_end=600", "bodies.dimorphos=~")
with read("alone.h5") as f:
    assert all(np.ndim(f["work"].attrs[k]) == 0 for k in ("steps", "wall_time", "outcome_checksum"))  # scalars
    assert f["particles/bodies/position/value"].shape[1] == 1
    assert "separation" not in f["observables"]  # no binary left

# A shaped body's mass replaces the scene's density: the density is mass / volume.
run(didymos, "light.h5", "run.t_end=600", "bodies.dimorphos.mass=4.3e9")
with read("light.h5") as f:
    assert f["particles/bodies/mass"][1] == 4.3e9
    shape = f["parameters/shapes/dimorphos"].attrs
    a, b, c = shape["semi_axes"]
    assert abs(shape["density"][0] - 4.3e9 / (4 / 3 * math.pi * a * b * c)) < 1e-9 * shape["density"][0]
# ... and by deleting the density first (the same scene)
run(didymos, "light2.h5", "run.t_end=600", "bodies.dimorphos.density=~", "bodies.dimorphos.mass=4.3e9")
with read("light.h5") as f, read("light2.h5") as g:
    assert np.array_equal(f["particles/bodies/position/value"][()], g["particles/bodies/position/value"][()])

# An ensemble varies a shaped body's mass.
p = subprocess.run([noether, "ensemble", didymos, "--vary", "bodies.dimorphos.mass=list(4.0e9, 4.6e9)",
                    "--samples", "2", "--set", "run.t_end=600", "--force", "-o", os.path.join(work, "ens.h5")],
                   capture_output=True, text=True)
assert p.returncode == 0, p.stderr[-800:]
with read("ens.h5") as f:
    assert sorted(f["inputs/bodies.dimorphos.mass"][()]) == [4.0e9, 4.6e9]
    units = {name: f[name].attrs["unit"] for name in ("summary/final_time", "summary/max_abs_energy_error",
                                                        "final/positions", "final/momenta", "orbit/a", "orbit/period")}
    assert units == {"summary/final_time": "s", "summary/max_abs_energy_error": "kg m^2/s^2",
                     "final/positions": "m", "final/momenta": "kg m/s", "orbit/a": "m", "orbit/period": "s"}, units
    assert list(f["outcome"][()]) == [0, 0], f["outcome"][()]
    final = f["final/positions"][()]
    assert np.linalg.norm(final[0] - final[1]) > 1e-6  # the masses made different runs

p = subprocess.run([noether, "ensemble", didymos, "--vary", "bodies.dimorphs.mass=normal(4e9, 1e8)", "--samples", "2",
                    "--force", "-o", os.path.join(work, "ens2.h5")], capture_output=True, text=True)
assert p.returncode == 2 and "--vary bodies.dimorphs.mass: the scene has no 'dimorphs' at 'bodies'; did you mean " \
    "'dimorphos'?" in p.stderr, p.stderr

for edit, message in [
    ("run.nope=~", "the scene has no 'run.nope' to delete"),
    ("bodies.zork=~", "'bodies' has no item 'zork' (it has 2, numbered from 0, or by name)"),
    ("integrator+=3", "'integrator' is not a list (+= appends to a list; = replaces)"),
    ("bodies.dimorphos.nope=~", "the scene has no 'bodies.dimorphos.nope' to delete"),
    ("bodies.dimorphs.mass=1e9", "the scene has no 'dimorphs' at 'bodies'; did you mean 'dimorphos'?"),
]:
    text = run(didymos, "refused.h5", edit, status=2)
    assert message in text, (edit, text)

# A copied scene without its shape files: where they were looked for.
copied = os.path.join(work, "copied")
os.makedirs(copied)
shutil.copy(didymos, copied)
text = run(os.path.join(copied, "didymos.yaml"), "refused.h5", status=2)
expect = f"shape file 'shapes/Didymos_A_vert_met.csv' not found (relative to the scene's folder: " \
         f"{os.path.realpath(copied)}/shapes/Didymos_A_vert_met.csv)"
assert expect in text or expect.replace(os.path.realpath(copied), copied) in text, text

# --- Euler angles ----------------------------------------------------------------------------


def rotation(yaw, pitch, roll):  # eq. 17.9, independently of the C++ code
    cz, sz, cy, sy, cx, sx = (math.cos(yaw), math.sin(yaw), math.cos(pitch), math.sin(pitch),
                              math.cos(roll), math.sin(roll))
    Rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    Ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    Rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    return Rz @ Ry @ Rx


run(didymos, "nominal.h5", "run.t_end=43200")
with read("nominal.h5") as f:
    angles = np.radians(f["particles/bodies/euler_angles/value"][()])
    R = f["checkpoint/attitude"][()]
    assert f["particles/bodies/euler_angles/value"].attrs["unit"] == "deg"
    worst = max(np.abs(rotation(*angles[i, k]) - R[i, k]).max() for i in range(0, len(R), 10) for k in range(2))
    assert worst < 1e-13, worst
    nominal = f["observables/secondary_euler_angles/value"][()]
    libration = f["observables/libration_angle/value"][()]
    assert np.abs(nominal[:, 0] + libration).max() < 1e-4, np.abs(nominal[:, 0] + libration).max()
    assert np.abs(nominal).max() < 1.0  # Dimorphos faces Didymos: small angles

# At t = 0 the orbit frame of didymos.yaml is Rz(180°) (Dimorphos on +x, moving along +y): an
# attitude of Euler angles (200, 10, −15) in the scene frame is (20, 10, −15) in the orbit frame.
run(didymos, "tilted.h5", "run.t_end=600", "bodies.dimorphos.attitude={euler_angles: [200, 10, -15]}")
with read("tilted.h5") as f:
    first = f["observables/secondary_euler_angles/value"][0]
    assert np.abs(first - [20, 10, -15]).max() < 1e-9, first
    assert np.abs(f["particles/bodies/euler_angles/value"][0, 1] - [-160, 10, -15]).max() < 1e-9

# A half turn about the ellipsoid's own z axis is a symmetry of the body: the same orbit, and
# the folded orbit-frame angles the same.
run(didymos, "turned.h5", "run.t_end=43200", "bodies.dimorphos.attitude={euler_angles: [180, 0, 0]}")
with read("turned.h5") as f:
    turned = f["observables/secondary_euler_angles/value"][()]
    assert np.abs(turned - nominal).max() < 1e-6, np.abs(turned - nominal).max()

print(f"scene_edits: body added/removed/reweighted, edits refused with reasons; Euler angles compose "
      f"back to R within {worst:.1e}, yaw = −libration within {np.abs(nominal[:, 0] + libration).max():.1e} deg, "
      f"a half-turned Dimorphos within {np.abs(turned - nominal).max():.1e} deg")
