#!/usr/bin/python3
"""Runs kepler.yaml with the stormer-verlet plugin at steps h and h/2 and checks what makes it
a symplectic method of order 2: the energy error falls by 4 (between 3.5 and 4.5) when the step
halves, and it stays bounded (its maximum over the second half of the run is no more than 1.5
times that over the first: no drift).

    check_order.py NOETHER SCENE OUT_DIR [--step 0.004]

NOETHER_PLUGIN_PATH must name the folder holding noether-stormer-verlet.so.
"""
import argparse
import os
import subprocess
import sys

import h5py
import numpy as np


def max_energy_errors(noether, scene, out, step):
    subprocess.run([noether, "run", scene, "--set", f"integrator.step={step}", "--force", "--no-progress",
                    "-o", out], check=True, stdout=subprocess.DEVNULL)
    with h5py.File(out, "r") as f:
        E = f["observables/energy/value"][:]
    dE = np.abs(E - E[0])
    half = len(dE) // 2
    return dE.max(), dE[:half].max(), dE[half:].max()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("noether")
    ap.add_argument("scene")
    ap.add_argument("out_dir")
    ap.add_argument("--step", type=float, default=0.004)
    a = ap.parse_args()
    os.makedirs(a.out_dir, exist_ok=True)
    coarse = max_energy_errors(a.noether, a.scene, os.path.join(a.out_dir, "coarse.h5"), a.step)
    fine = max_energy_errors(a.noether, a.scene, os.path.join(a.out_dir, "fine.h5"), a.step / 2)
    ratio = coarse[0] / fine[0]
    print(f"max |E - E0|: {coarse[0]:.3e} (h = {a.step}), {fine[0]:.3e} (h/2): ratio {ratio:.2f}")
    print(f"first half {fine[1]:.3e}, second half {fine[2]:.3e}")
    ok = 3.5 <= ratio <= 4.5 and fine[2] <= 1.5 * fine[1] and coarse[2] <= 1.5 * coarse[1]
    print("order 2 and bounded energy error" if ok else "FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
