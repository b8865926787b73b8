#!/usr/bin/python3
"""plot_fit.py FIT.json OUT.png

The residuals of a `noether fit` (docs/fitting.md): each observation's residual over its sigma
against time, one colour per observable, with the ±1σ and ±3σ bands; the title gives χ² and
the degrees of freedom. Prints how many residuals lie beyond 3σ."""
import argparse
import json

from plot_common import pyplot

plt, np = pyplot(__file__, "numpy")

parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("fit")
parser.add_argument("out")
args = parser.parse_args()

with open(args.fit) as f:
    fit = json.load(f)
residuals = fit["residuals"]
t = np.array([r["t"] for r in residuals])
z = np.array([r["normalized"] for r in residuals])
kinds = [f"{r['observable']} {r['target']}–{r['center']}" for r in residuals]
fig, ax = plt.subplots(figsize=(7.0, 4.2))
for band, shade in ((3, "#eeeeee"), (1, "#dddddd")):
    ax.axhspan(-band, band, color=shade, zorder=0)
for kind in dict.fromkeys(kinds):
    mask = np.array([k == kind for k in kinds])
    ax.plot(t[mask], z[mask], "o", ms=3.5, label=kind)
ax.axhline(0, color="k", lw=0.8)
ax.set_xlabel("t (the scene's unit of time)")
ax.set_ylabel("(observed − computed) / σ")
names = ", ".join(p["name"] for p in fit["parameters"])
ax.set_title(f"χ² = {fit['chi2']:.4g} for {fit['degrees_of_freedom']} degrees of freedom; fitted: {names}", fontsize=8)
ax.legend(fontsize=7, loc="upper right")
fig.tight_layout()
fig.savefig(args.out, dpi=110)
print(f"{'residuals beyond 3 sigma':<29} {int(np.sum(np.abs(z) > 3))} of {len(z)}")
