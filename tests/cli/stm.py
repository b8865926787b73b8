"""stm.py NOETHER SOURCE_DIR WORK_DIR: `noether run --stm` (docs/derivatives.md) as a user meets it.

The file's /derivatives/stm starts at the identity, is named by /derivatives/coordinates, has
det 1 at every frame (the LGVI's map is symplectic), and its column of alpha's x position at the
last frame is the central difference of two runs started from positions moved with --set; the
file resumed to a later t_end holds the STM of a run straight there, to the bit. A method
without a tangent map (cvode in the relative frame) is refused before anything is written. `--sensitivity KEY` writes
/derivatives/sensitivity, checked the same way, and refuses a key it cannot derive (a dumbbell's
length).
"""
import os
import subprocess
import sys

import h5py
import numpy as np

noether, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
os.chdir(work)
scene = os.path.join(src, "examples", "dumbbells.yaml")
base = ["--no-progress", "--force", "--set", "run.t_end=0.5", "--set", "run.output_every=0.1"]

subprocess.run([noether, "run", scene, "--stm", "-o", "stm.h5", *base], check=True, stdout=subprocess.DEVNULL)
with h5py.File("stm.h5", "r") as f:
    stm = f["derivatives/stm/value"][:]
    names = [n.decode() if isinstance(n, bytes) else n for n in f["derivatives/coordinates"][:]]
    assert np.array_equal(f["derivatives/stm/time"][:], f["particles/bodies/position/time"][:])
assert stm.shape == (6, 24, 24), stm.shape
assert names[:4] == ["alpha.position.x", "alpha.position.y", "alpha.position.z", "beta.position.x"], names[:4]
assert names[6] == "alpha.attitude.x" and names[12] == "alpha.momentum.x" and names[23] == "beta.angular_momentum.z"
assert np.array_equal(stm[0], np.eye(24))
dets = [np.linalg.det(m) for m in stm]
assert max(abs(d - 1) for d in dets) < 1e-12, dets


def final_state(override):
    """Positions and momenta at the last frame of a run with one more --set."""
    subprocess.run([noether, "run", scene, "-o", "moved.h5", *base, "--set", override],
                   check=True, stdout=subprocess.DEVNULL)
    with h5py.File("moved.h5", "r") as f:
        return np.concatenate([f["particles/bodies/position/value"][-1].ravel(),
                               f["checkpoint/linear_momentum"][-1].ravel()])


h = 1e-6
def final_positions(x):
    return final_state(f"bodies.alpha.position=[{x!r}, 0, 0.2]")


column = (final_positions(0.67 + h) - final_positions(0.67 - h)) / (2 * h)
expected = np.concatenate([stm[-1][0:6, 0], stm[-1][12:18, 0]])
error = np.abs(column - expected).max() / np.abs(expected).max()
assert error < 1e-6, (error, column, expected)

# --sensitivity: the column of alpha's initial y velocity, against two runs moved with --set.
subprocess.run([noether, "run", scene, "--sensitivity", "bodies.alpha.velocity.1", "-o", "sens.h5", *base],
               check=True, stdout=subprocess.DEVNULL)
with h5py.File("sens.h5", "r") as f:
    sens = f["derivatives/sensitivity/value"][:]
    keys = [n.decode() if isinstance(n, bytes) else n for n in f["derivatives/parameters"][:]]
    assert "derivatives/stm" not in f
assert sens.shape == (6, 24, 1) and keys == ["bodies.alpha.velocity.1"], (sens.shape, keys)


def final_state_moved(v):
    return final_state(f"bodies.alpha.velocity=[0, {v!r}, 0]")


column = (final_state_moved(0.67 + h) - final_state_moved(0.67 - h)) / (2 * h)
expected = np.concatenate([sens[-1][0:6, 0], sens[-1][12:18, 0]])
sens_error = np.abs(column - expected).max() / np.abs(expected).max()
assert sens_error < 1e-6, (sens_error, column, expected)
length = subprocess.run([noether, "run", scene, "--sensitivity", "bodies.beta.shape.dumbbell.length", "-o",
                         "length.h5", *base], capture_output=True, text=True)
assert length.returncode == 2 and "of a shape: an ellipsoid's semi-axes, a polyhedron's scale" in length.stderr, length.stderr
assert not os.path.exists("length.h5")

# --resume: the finished file extended to t = 1 holds the STM a run straight to t = 1 holds, to
# the bit (read back from its frames: docs/derivatives.md, "Continuing").
subprocess.run([noether, "run", "--resume", "stm.h5", "--t-end", "1", "--no-progress"], check=True,
               stdout=subprocess.DEVNULL)
subprocess.run([noether, "run", scene, "--stm", "-o", "straight.h5", *base, "--set", "run.t_end=1"], check=True,
               stdout=subprocess.DEVNULL)
with h5py.File("stm.h5", "r") as f, h5py.File("straight.h5", "r") as g:
    assert f["derivatives/stm/value"].shape == (11, 24, 24), f["derivatives/stm/value"].shape
    assert np.array_equal(f["derivatives/stm/value"][:], g["derivatives/stm/value"][:])
if os.path.exists("refused.h5"):
    os.remove("refused.h5")  # from an earlier run of this test
refused = subprocess.run([noether, "run", scene, "--stm", "-o", "refused.h5", *base, "--set", "integrator={plugin: cvode, frame: relative}"],
                         capture_output=True, text=True)
assert refused.returncode == 2 and "cannot carry the state-transition matrix" in refused.stderr, refused.stderr
assert not os.path.exists("refused.h5")
print(f"stm: 6 frames of 24×24, max |det − 1| {max(abs(d - 1) for d in dets):.1e}; "
      f"column alpha.position.x against differences of two runs: {error:.1e}; sensitivity to "
      f"bodies.alpha.velocity.1: {sens_error:.1e}")
