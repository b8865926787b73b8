#!/usr/bin/python3
"""Draws a stability spectrum in the complex plane: the multipliers of a periodic orbit with the
unit circle (`noether orbit stability --plot`), or the eigenvalues of a relative equilibrium's
linearisation with the imaginary axis (`noether orbit equilibrium --plot`), from the CSV the
command writes next to the picture (columns re, im, label).

    tools/plot_spectrum.py SPECTRUM.csv OUT.png --kind multipliers|eigenvalues [--scale S] [--title T]

Eigenvalues are drawn divided by --scale (the equilibrium's rate ω). A multiplier outside the
unit circle, or an eigenvalue off the imaginary axis, is drawn in red: an unstable direction.
"""
import argparse
import csv
import math

from plot_common import pyplot

plt = pyplot(__file__)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("png")
    ap.add_argument("--kind", choices=["multipliers", "eigenvalues"], required=True)
    ap.add_argument("--scale", type=float, default=1.0, help="divide eigenvalues by this (the rate ω)")
    ap.add_argument("--tolerance", type=float, default=1e-6, help="what counts as on the circle or the axis")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    with open(a.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    z = [complex(float(r["re"]), float(r["im"])) for r in rows]
    wide = a.kind == "multipliers" and max([0.0] + [abs(w) for w in z]) > 3
    if wide:  # large multipliers: the unit circle up close, and log |μ| against arg μ beside it
        fig, (ax, side) = plt.subplots(1, 2, figsize=(10, 5))
        side.axhline(0, color="0.6", lw=0.8)
        for w in z:
            if abs(w) > 0:
                side.plot(math.degrees(math.atan2(w.imag, w.real)), math.log10(abs(w)), "o", ms=6,
                          color="tab:red" if abs(w) > 1 + a.tolerance else "tab:blue",
                          mfc=None if abs(w) > 1 + a.tolerance else "none")
        side.set_xlim(-190, 190)
        side.set_xlabel("arg μ [deg]")
        side.set_ylabel("log10 |μ|")
        side.grid(lw=0.3)
    else:
        fig, ax = plt.subplots(figsize=(5.5, 5.5))
    if a.kind == "multipliers":
        t = [2 * math.pi * k / 400 for k in range(401)]
        ax.plot([math.cos(s) for s in t], [math.sin(s) for s in t], color="0.6", lw=0.8, label="unit circle")
        unstable = [abs(w) > 1 + a.tolerance for w in z]
        ax.set_xlabel("Re μ")
        ax.set_ylabel("Im μ")
        ax.set_aspect("equal")
        reach = 1.5 if wide else max([1.1] + [abs(w) * 1.1 for w in z])
    else:
        z = [w / a.scale for w in z]
        ax.axvline(0, color="0.6", lw=0.8, label="imaginary axis")
        top = max([1.0] + [abs(w) for w in z])
        unstable = [abs(w.real) > a.tolerance * top for w in z]
        ax.set_xlabel("Re λ / ω")
        ax.set_ylabel("Im λ / ω")
        reach = 1.1 * top
    stable_z = [w for w, u in zip(z, unstable) if not u]
    unstable_z = [w for w, u in zip(z, unstable) if u]
    on, off = ("|μ| ≤ 1", "|μ| > 1: unstable") if a.kind == "multipliers" else ("Re λ = 0", "Re λ ≠ 0: unstable")
    ax.plot([w.real for w in stable_z], [w.imag for w in stable_z], "o", color="tab:blue", ms=6, mfc="none",
            label=f"{on} ({len(stable_z)})")
    if unstable_z:
        ax.plot([w.real for w in unstable_z], [w.imag for w in unstable_z], "o", color="tab:red", ms=6,
                label=f"{off} ({len(unstable_z)})")
    placed = []  # the mode each eigenvalue belongs to, where the command named it; close ones left
    for w, r in zip(z, rows):
        if r.get("label"):
            left = any(abs(w - p) < 0.04 * reach for p in placed)
            placed.append(w)
            ax.annotate(r["label"], (w.real, w.imag), xytext=(-6 if left else 6, 0), textcoords="offset points",
                        fontsize=6, va="center", ha="right" if left else "left")
    ax.set_xlim(-reach, reach)
    ax.set_ylim(-reach, reach)
    ax.grid(lw=0.3)
    ax.legend(fontsize=7, loc="upper right")
    (fig.suptitle if wide else ax.set_title)(a.title, fontsize=8)
    fig.tight_layout()
    fig.savefig(a.png, dpi=90)


if __name__ == "__main__":
    main()
