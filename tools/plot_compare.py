#!/usr/bin/python3
"""Draws the work–precision diagram of a `noether compare` table (CSV): wall time against
final position error, max energy error and max ‖I − RᵀR‖, one line per integrator family.

    tools/plot_compare.py COMPARE.csv OUT.png [--title TITLE]
"""
import argparse
import sys
import csv
from collections import defaultdict

try:
    import matplotlib
except ImportError:  # exit 3: the driver then tries Debian's /usr/bin/python3
    sys.stderr.write(f"{__file__}: matplotlib is not available to {sys.executable}\n")
    sys.exit(3)

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


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
    panels = [("final_position_error", "final position error  max‖x − x_ref‖"),
              ("max_abs_energy_error", "max |E − E0|"),
              ("max_orthogonality_error", "max ‖I − RᵀR‖_F")]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.8))
    for ax, (key, label) in zip(axes, panels):
        for name, rows in sorted(families.items()):
            pts = sorted((float(r[key]), float(r["wall_seconds"])) for r in rows)
            pts = [(max(e, 1e-17), max(w, 1e-5)) for e, w in pts]
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=name)
        ax.set_xlabel(label)
        ax.set_ylabel("wall time [s] (median)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle(f"work–precision: {args.title}")
    fig.tight_layout()
    fig.savefig(args.png, dpi=90)


if __name__ == "__main__":
    main()
