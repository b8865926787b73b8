#!/usr/bin/python3
"""Draws the normal-mode frequencies of a family of relative equilibria against the fixed value
(`noether orbit equilibrium --sweep ... --plot`), from the CSV the command writes next to the
picture (one row per mode: value, rate, linear, energetic, frequency, growth). Oscillations are
drawn as frequencies, real pairs as growth rates in red; members that are linearly unstable are
shaded red, those stable only gyroscopically (linearly stable, not a minimum of the energy) amber.

    tools/plot_equilibrium_sweep.py SWEEP.csv OUT.png [--xlabel NAME] [--title T]
"""
import argparse
import csv
from collections import OrderedDict

from plot_common import pyplot

plt = pyplot(__file__)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("png")
    ap.add_argument("--xlabel", default="separation")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    with open(a.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    members = OrderedDict()
    for r in rows:
        members.setdefault(float(r["value"]), []).append(r)
    values = list(members)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    # Shade each member's verdict over the half-way points to its neighbours.
    edges = [values[0]] + [(u + v) / 2 for u, v in zip(values, values[1:])] + [values[-1]]
    for k, v in enumerate(values):
        first = members[v][0]
        if first["linear"] != "linearly stable":
            ax.axvspan(edges[k], edges[k + 1], color="tab:red", alpha=0.12, lw=0)
        elif first["energetic"] != "energetically stable":
            ax.axvspan(edges[k], edges[k + 1], color="tab:orange", alpha=0.15, lw=0)
    freq = [(v, float(r["frequency"])) for v in values for r in members[v] if float(r["frequency"]) > 0]
    grow = [(v, float(r["growth"])) for v in values for r in members[v] if float(r["frequency"]) == 0
            and float(r["growth"]) > 0]
    rate = [(v, float(members[v][0]["rate"])) for v in values]
    ax.plot([p[0] for p in rate], [p[1] for p in rate], "-", color="0.5", lw=1, label="rate ω")
    ax.plot([p[0] for p in freq], [p[1] for p in freq], "o", color="tab:blue", ms=4, label="mode frequency")
    if grow:
        ax.plot([p[0] for p in grow], [p[1] for p in grow], "x", color="tab:red", ms=6, label="growth rate (real pair)")
    ax.set_yscale("log")
    ax.set_xlabel(a.xlabel)
    ax.set_ylabel("frequency or growth rate (turning frame)")
    ax.plot([], [], "s", color="tab:red", alpha=0.3, label="linearly unstable")
    ax.plot([], [], "s", color="tab:orange", alpha=0.3, label="stable only gyroscopically")
    ax.legend(fontsize=7)
    ax.grid(lw=0.3, which="both")
    ax.set_title(a.title, fontsize=8)
    fig.tight_layout()
    fig.savefig(a.png, dpi=90)


if __name__ == "__main__":
    main()
