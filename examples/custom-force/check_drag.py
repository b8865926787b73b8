#!/usr/bin/python3
"""Runs drifting-rock.yaml with the linear-drag plugin at steps h and h/2 against the exact
solution v(t) = v0 e^(−k t), x(t) = x0 + v0 (1 − e^(−k t)) / k, Ω(t) = Ω0 e^(−k_s t): the
error falls by 4 when the step halves (the forced LGVI is of order 2), the work the drag did is
the kinetic energy lost to round-off (the balance, docs/equations.md eq. 33.4), and the run's
verdict is trustworthy.

    check_drag.py NOETHER SCENE OUT_DIR

NOETHER_PLUGIN_PATH must name the folder holding noether-linear-drag.so.
"""
import os
import subprocess
import sys

import h5py
import numpy as np

noether, scene, out_dir = sys.argv[1:4]
os.makedirs(out_dir, exist_ok=True)
k, ks, m = 0.5, 0.2, 2.0
v0, w0 = np.array([1.0, 0.5, 0.0]), 3.0


def errors(step):
    out = os.path.join(out_dir, f"drag-{step}.h5")
    p = subprocess.run([noether, "run", scene, "--set", f"integrator.step={step}", "--force", "--no-progress", "-o", out],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stdout + p.stderr
    assert "verdict                       trustworthy" in p.stdout, p.stdout
    with h5py.File(out, "r") as f:
        t = f["particles/bodies/position/time"][:]
        x = f["particles/bodies/position/value"][:, 0]
        v = f["particles/bodies/velocity/value"][:, 0]
        w = np.linalg.norm(f["particles/bodies/angular_velocity/value"][:, 0], axis=1)
        W = f["observables/force_balance/value"][:, 0, 0]
        E = f["observables/energy/value"][:]
    decay = np.exp(-k * t)[:, None]
    x_exact = v0 * (1 - decay) / k
    err = max(np.abs(x - x_exact).max(), np.abs(v - v0 * decay).max(), np.abs(w - w0 * np.exp(-ks * t)).max())
    balance = np.abs(E - W - E[0]).max() / np.abs(W).max()
    return err, balance


coarse, fine = errors(0.02), errors(0.01)
ratio = coarse[0] / fine[0]
print(f"error against e^(-k t): {coarse[0]:.3e} (h = 0.02), {fine[0]:.3e} (h = 0.01): ratio {ratio:.2f}; "
      f"|E - W - E0| / max|W| {max(coarse[1], fine[1]):.1e}")
assert 3.5 < ratio < 4.5, ratio
assert max(coarse[1], fine[1]) < 1e-13
