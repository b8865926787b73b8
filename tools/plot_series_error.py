#!/usr/bin/python3
"""Plot the error of the inertia-integral series against the exact reference, per order.

Reads the tables that the mutual-potential tests print, e.g.

    build/release/bin/noether_tests --gtest_filter='MutualSeries.ConvergesToTheExact*' \
        | python3 tools/plot_series_error.py -o series-error.png

Each table starts with a line "<configuration>  N   rel U      rel F      torque" followed by
rows "N  relU  relF  torque".
"""
import argparse
import re
import sys

from plot_common import pyplot

plt = pyplot(__file__)


def parse(lines):
    tables, name = {}, None
    header = re.compile(r"^(\S+)\s+N\s+rel U\s+rel F\s+torque")
    row = re.compile(r"^\s+(\d+)\s+([0-9.e+-]+)\s+([0-9.e+-]+)\s+([0-9.e+-]+)\s*$")
    for line in lines:
        m = header.match(line)
        if m:
            name = m.group(1)
            tables[name] = []
            continue
        m = row.match(line)
        if m and name:
            tables[name].append(tuple(float(x) for x in m.groups()))
    return {k: v for k, v in tables.items() if v}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--output", required=True, help="PNG file to write")
    args = ap.parse_args()
    tables = parse(sys.stdin)
    if not tables:
        sys.exit("plot_series_error.py: no tables found on standard input")
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2), sharex=True)
    for name, rows in tables.items():
        N = [r[0] for r in rows]
        for ax, k in zip(axes, (1, 2, 3)):
            ax.semilogy(N, [max(r[k], 1e-16) for r in rows], "o-", ms=3, label=name)
    titles = ("potential U: |U_N − U| / |U|", "force: |F_N − F| / |F|", "torques: max |τ_N − τ| / (|R| |F|)")
    for ax, title in zip(axes, titles):
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("series order N (total degree)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("relative error against mutual-exact")
    axes[0].legend(fontsize=8)
    fig.suptitle("Inertia-integral series against the exact mutual potential", fontsize=11)
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    print(f"plot: {args.output} ({len(tables)} configurations)")


if __name__ == "__main__":
    main()
