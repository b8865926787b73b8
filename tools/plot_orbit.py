#!/usr/bin/python3
"""Draws the curves of a periodic orbit found by `noether orbit find` (its .csv).

    tools/plot_orbit.py ORBIT.csv ORBIT.png [--title TITLE]
"""
import argparse
import csv

from plot_common import pyplot

plt = pyplot(__file__)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("png")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    with open(a.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    n = (len(rows[0]) - 1) // 2
    fig, ax = plt.subplots(figsize=(5, 5))
    for j in range(1, n + 1):
        x = [float(r[f"x{j}"]) for r in rows]
        y = [float(r[f"y{j}"]) for r in rows]
        ax.plot(x, y, lw=1)
        ax.plot(x[0], y[0], "o", ms=5)
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_title(a.title, fontsize=7)
    fig.tight_layout()
    fig.savefig(a.png, dpi=90)


if __name__ == "__main__":
    main()
