#!/usr/bin/python3
"""Draws the work–precision diagram of a `noether compare` table (CSV): wall time against
final position error, max energy error and max ‖I − RᵀR‖ (rigid bodies only), one line per
integrator family. From the compare file next to the CSV (same name, .h5) it takes the units
and the reference's estimated error, drawn as the floor below which position errors are not
measured.

    tools/plot_compare.py COMPARE.csv OUT.png [--title TITLE]
"""
import argparse
import csv
import math
import os
from collections import defaultdict

from plot_common import pyplot

plt = pyplot(__file__)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("png")
    ap.add_argument("--title", default="")
    args = ap.parse_args()
    families = defaultdict(list)
    with open(args.csv, newline="") as f:
        for row in csv.DictReader(f):
            if row["ok"] == "1":
                families[row["family"]].append(row)
    length, energy, floor = "", "", float("nan")
    h5 = os.path.splitext(args.csv)[0] + ".h5"
    try:
        import h5py
        with h5py.File(h5, "r") as f:
            attrs = f["compare"].attrs
            floor = float(attrs["reference_error"])
            length, energy = attrs.get("unit_length", ""), attrs.get("unit_energy", "")
    except Exception:  # no compare file or no h5py: no floor and no units, still a plot
        pass
    unit = lambda u: f" [{u}]" if u and u != "1" else ""  # noqa: E731
    panels = [("final_position_error", "final position error  max‖x − x_ref‖" + unit(length)),
              ("max_abs_energy_error", "max |E − E0|" + unit(energy))]
    if any(float(r["max_orthogonality_error"]) > 0 for rows in families.values() for r in rows):
        panels.append(("max_orthogonality_error", "max ‖I − RᵀR‖_F"))
    fig, axes = plt.subplots(1, len(panels), figsize=(5 * len(panels), 4.8))
    for ax, (key, label) in zip(axes, panels):
        for name, rows in sorted(families.items()):
            pts = sorted((float(r[key]), float(r["wall_seconds"])) for r in rows)
            pts = [(max(e, 1e-17), max(w, 1e-5)) for e, w in pts]
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=name)
        ax.set_xlabel(label)
        ax.set_ylabel("wall time [s] (median)")
        ax.grid(True, which="both", alpha=0.3)
    if math.isfinite(floor) and floor > 0:  # errors below the reference's own are not measured
        left, right = axes[0].get_xlim()
        left = min(left, floor / 10)
        axes[0].axvspan(left, floor, color="0.88", zorder=0)
        axes[0].axvline(floor, color="0.4", ls="--", lw=1, label=f"reference error {floor:.1e}")
        axes[0].set_xlim(left, right)
    axes[0].legend(fontsize=8)
    fig.suptitle(f"work–precision: {os.path.basename(args.title)}")
    fig.tight_layout()
    fig.savefig(args.png, dpi=90)


if __name__ == "__main__":
    main()
