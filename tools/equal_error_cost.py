#!/usr/bin/python3
"""From a `noether compare` CSV: for each run of one family (default lgvi), the wall time the
cheapest other family would need for the same error, by log-log interpolation along that
family's settings. Prints the cost ratio (family / best other) at equal max |E − E0| and at
equal final position error.

    tools/equal_error_cost.py COMPARE.csv [--family lgvi]
"""
import argparse
import csv
import math
from collections import defaultdict


def cost_at(points, error):
    """Wall time for `error` on a family's (error, time) curve: log-log interpolated inside the
    measured range, or the cheapest measured run at least as accurate; None if neither."""
    pts = sorted(points)
    costs = [w for e, w in pts if e <= error]
    for (e0, w0), (e1, w1) in zip(pts, pts[1:]):
        if e0 <= error <= e1 and e0 > 0 and e1 > e0:
            f = (math.log(error) - math.log(e0)) / (math.log(e1) - math.log(e0))
            costs.append(math.exp(math.log(w0) + f * (math.log(w1) - math.log(w0))))
    return min(costs) if costs else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("--family", default="lgvi")
    a = ap.parse_args()
    fam = defaultdict(list)
    with open(a.csv, newline="") as f:
        for r in csv.DictReader(f):
            if r["ok"] == "1":
                fam[r["family"]].append(r)
    for key in ("max_abs_energy_error", "final_position_error"):
        print(f"equal {key}:")
        for r in fam[a.family]:
            err, wall = float(r[key]), float(r["wall_seconds"])
            best = None
            for name, rows in fam.items():
                if name == a.family:
                    continue
                c = cost_at([(float(x[key]), float(x["wall_seconds"])) for x in rows], err)
                if c is not None and (best is None or c < best[1]):
                    best = (name, c)
            if best:
                print(f"  {a.family} {r['setting']}: error {err:.3g}, {wall:.4f} s; cheapest other "
                      f"{best[0]} {best[1]:.4f} s; ratio {wall / best[1]:.1f}")
            else:
                print(f"  {a.family} {r['setting']}: error {err:.3g}: no other family spans it")


if __name__ == "__main__":
    main()
