#!/usr/bin/python3
"""plot_ensemble.py ENS.h5 OUT.png [--nominal NOMINAL.h5] [--quantity orbit/period]

A histogram of one quantity over the completed samples of a `noether ensemble` file
(docs/ensembles.md): by default the mutual orbit's period, in hours, or, with --nominal (the
ensemble file of the unperturbed scene, one sample), its change from the nominal period in
minutes. Prints the mean and standard deviation it plots."""
import argparse

from plot_common import pyplot

plt, h5py, np = pyplot(__file__, "h5py", "numpy")

parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("ensemble")
parser.add_argument("out")
parser.add_argument("--nominal", help="an ensemble file of the unperturbed scene: plot the change from it")
parser.add_argument("--quantity", default="orbit/period", help="a dataset of the file [sample] (default orbit/period)")
args = parser.parse_args()

with h5py.File(args.ensemble, "r") as f:
    values = f[args.quantity][()]
    done = f["outcome"][()] == 0
    units = f.attrs.get("units", "")
    varied = [f"{k}: {f['inputs'][k].attrs['distribution'].split('=', 1)[1]}" for k in f["inputs"]]
values = values[done & np.isfinite(values)]
is_period = args.quantity == "orbit/period"
label = args.quantity
if args.nominal:
    with h5py.File(args.nominal, "r") as f:
        nominal = f[args.quantity][0]
    values = values - nominal
    label = f"change in {args.quantity}"
if is_period:  # seconds in an SI scene: minutes for a change, hours for a period
    scale, unit = (60.0, "min") if args.nominal else (3600.0, "h")
    if "SI" not in units and "s" not in units:
        scale, unit = 1.0, "time units"
    values = values / scale
else:
    unit = ""
print(f"{'quantity':<29} {label} [{unit}]")
print(f"{'completed samples':<29} {len(values)}")
print(f"{'mean':<29} {values.mean():.4g}")
print(f"{'standard deviation':<29} {values.std(ddof=1) if len(values) > 1 else 0.0:.3g}")
fig, ax = plt.subplots(figsize=(6.5, 4.2))
ax.hist(values, bins=max(5, int(np.sqrt(len(values)))), color="#4477aa")
ax.axvline(values.mean(), color="k", lw=1)
ax.set_xlabel(f"{label} [{unit}]" if unit else label)
ax.set_ylabel("samples")
ax.set_title("; ".join(varied), fontsize=8)
fig.tight_layout()
fig.savefig(args.out, dpi=110)
print(f"plot: {args.out}")
