#!/usr/bin/python3
"""Measures the nodal regression of the probe in a j2-orbit run and compares it with the
analytic secular J2 rate dΩ/dt = −(3/2) n J2 (Re/a)² cos i / (1 − e²)².

    check_precession.py RUN.h5 [--J2 1e-3] [--radius 1] [--tolerance 0.01]

Exits 1 when the measured rate differs from the analytic one by more than the tolerance.
"""
import argparse
import sys

import h5py
import numpy as np


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("run")
    ap.add_argument("--J2", type=float, default=1e-3)
    ap.add_argument("--radius", type=float, default=1.0)
    ap.add_argument("--tolerance", type=float, default=0.01)
    a = ap.parse_args()
    with h5py.File(a.run, "r") as f:
        t = f["particles/bodies/position/time"][:]
        x = f["particles/bodies/position/value"][:]
        v = f["particles/bodies/velocity/value"][:]
        G = float(f["parameters"].attrs["G"])
        q = f["particles/bodies/orientation/value"][:, 0, :]  # the planet's attitude
    mass_planet = 1.0  # as in j2-orbit.yaml
    mu = G * mass_planet
    r = x[:, 1, :] - x[:, 0, :]
    w = v[:, 1, :] - v[:, 0, :]
    h = np.cross(r, w)
    node = np.unwrap(np.arctan2(h[:, 0], -h[:, 1]))
    slope = np.polyfit(t, node, 1)[0]
    # Mean elements over the run (osculating elements oscillate at O(J2)).
    rn = np.linalg.norm(r, axis=1)
    energy = 0.5 * np.sum(w * w, axis=1) - mu / rn
    sma = np.mean(-mu / (2 * energy))
    inc = np.mean(np.arccos(h[:, 2] / np.linalg.norm(h, axis=1)))
    ecc = np.mean(np.linalg.norm(np.cross(w, h) / mu - r / rn[:, None], axis=1))
    n = np.sqrt(mu / sma**3)
    analytic = -1.5 * n * a.J2 * (a.radius / sma) ** 2 * np.cos(inc) / (1 - ecc**2) ** 2
    rel = abs(slope - analytic) / abs(analytic)
    print(f"orbits: {t[-1] * n / (2 * np.pi):.1f}, a = {sma:.6f}, e = {ecc:.2e}, "
          f"i = {np.degrees(inc):.4f} deg")
    print(f"nodal rate measured {slope:.6e}, analytic {analytic:.6e}, relative difference {rel:.2e}")
    if rel > a.tolerance:
        print(f"FAIL: differs by more than {a.tolerance:.0%}")
        return 1
    print(f"PASS (tolerance {a.tolerance:.0%})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
