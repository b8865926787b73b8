"""fit.py NOETHER SOURCE_DIR WORK_DIR: `noether fit` as a user meets it (docs/fitting.md).

The DART-like example: data made with a known Δv by `noether observe --noise`, fitted from the
scene's first guess; the estimate within 3σ of the truth, the JSON's fields consistent with
each other (σ² the covariance's diagonal, residuals observed − computed, χ² their normalised
sum of squares); the command's refusals (exit 2) by name.
"""
import json
import os
import subprocess
import sys

import numpy as np

noether, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
os.chdir(work)
scene = os.path.join(src, "examples", "didymos-dart.yaml")
epochs = os.path.join(src, "examples", "observations", "dart-epochs.csv")
truth = -0.0027


def noether_run(*args, check=True):
    return subprocess.run([noether, *args], capture_output=True, text=True, check=check)


noether_run("run", scene, "--no-progress", "--force", "--set", f"impulses.0.delta_v.1={truth}", "-o", "truth.h5")
noether_run("observe", "truth.h5", "--at", epochs, "--noise", "--seed", "11", "-o", "observed.csv", "--force")
out = noether_run("fit", scene, "--observations", "observed.csv", "--free", "impulses.0.delta_v.1",
                  "--free", "bodies.dimorphos.density", "-o", "fit.json", "--plot", "residuals.png", "--force").stdout
print(out)
assert "plot: residuals.png" in out and os.path.getsize("residuals.png") > 10000, out
fit = json.load(open("fit.json"))
assert fit["converged"] and fit["observations"] == 72 and fit["degrees_of_freedom"] == 70, fit["stop"]
p = {x["name"]: x for x in fit["parameters"]}
dv = p["impulses.0.delta_v.1"]
assert dv["initial"] == -0.002 and abs(dv["estimate"] - truth) < 3 * dv["sigma"], dv
assert abs(p["bodies.dimorphos.density"]["estimate"] - 2203.111036687207) < 3 * p["bodies.dimorphos.density"]["sigma"]
cov = np.array(fit["covariance"])
sigma = np.array([x["sigma"] for x in fit["parameters"]])
assert np.allclose(np.sqrt(np.diag(cov)), sigma, rtol=1e-12)
assert np.allclose(np.array(fit["correlation"]), cov / np.outer(sigma, sigma), rtol=1e-12, atol=1e-15)
res = fit["residuals"]
assert len(res) == 72 and res[0]["target"] == "dimorphos" and res[0]["center"] == "didymos"
assert all(abs(r["residual"] - (r["observed"] - r["computed"])) < 1e-9 for r in res)
assert abs(sum(r["normalized"] ** 2 for r in res) - fit["chi2"]) < 1e-9 * fit["chi2"]
print(f"Δv = {dv['estimate'] * 1e3:.4f} ± {dv['sigma'] * 1e3:.4f} mm/s (truth {truth * 1e3} mm/s); "
      f"χ² {fit['chi2']:.1f} for {fit['degrees_of_freedom']}")

# The estimate's overrides remake the scene at the estimate: a run with them observed at the
# epochs gives the fit's computed values.
sets = [a for o in fit["overrides"] for a in ("--set", o)]
noether_run("run", scene, "--no-progress", "--force", *sets, "--set", "run.output_every=600", "-o", "estimate.h5")
again = noether_run("observe", "estimate.h5", "--at", epochs).stdout.splitlines()
computed = [float(line.split(",")[4]) for line in again if line and line[0].isdigit()]
assert max(abs(a - r["computed"]) for a, r in zip(computed, res)) < 1e-6, "the overrides do not remake the fit"



# The residual plot alone: its JSON beside it (a fit refused before it runs: an existing file).
refused_plot = noether_run("fit", scene, "--observations", "observed.csv", "--free", "impulses.0.delta_v.1",
                           "--plot", "fit.png", check=False)
assert refused_plot.returncode == 2 and "fit.json exists" in refused_plot.stderr, refused_plot.stderr

# An ensemble from the fit: its keys drawn jointly from the estimate and covariance.
import h5py  # noqa: E402

noether_run("ensemble", scene, "--from-fit", "fit.json", "--samples", "6", "--threads", "2", "-o", "ens.h5", "--force")
with h5py.File("ens.h5", "r") as f:
    drawn = f["inputs/impulses.0.delta_v.1"][:]
    density = f["inputs/bodies.dimorphos.density"][:]
    assert "fit(fit.json; mean" in f["inputs/impulses.0.delta_v.1"].attrs["distribution"]
    assert list(f["outcome"][:]) == [0] * 6
z = (drawn - dv["estimate"]) / dv["sigma"]
assert np.all(np.abs(z) < 5) and np.std(z) > 0.2, z
# The draws carry the fit's correlation (0.95): the density's deviations follow Δv's.
assert np.corrcoef(drawn, density)[0, 1] > 0.5, np.corrcoef(drawn, density)
print(f"ensemble from the fit: 6 samples, Δv within {np.max(np.abs(z)):.1f}σ of the estimate, "
      f"correlation with the density {np.corrcoef(drawn, density)[0, 1]:.2f}")


def refused(expect, *args):
    p = noether_run("fit", scene, *args, check=False)
    assert p.returncode == 2 and expect in p.stderr, (args, p.returncode, p.stderr)


with open("late.csv", "w") as f:
    f.write("t,observable,target,center,value,sigma\n-60,range,dimorphos,didymos,1200,1\n")
refused("late.csv:2: t = -60 is before the run starts (t0 = 0)", "--observations", "late.csv", "--free",
        "impulses.0.delta_v.1")
with open("body.csv", "w") as f:
    f.write("t,observable,target,center,value,sigma\n600,range,dimorphus,didymos,1200,1\n")
refused("body.csv:2: column 'target': no body 'dimorphus'", "--observations", "body.csv", "--free", "impulses.0.delta_v.1")
with open("sigma.csv", "w") as f:
    f.write("t,observable,target,center,value,sigma\n600,range,dimorphos,didymos,1200,0\n")
refused("sigma.csv:2: column 'sigma': must be positive (got 0)", "--observations", "sigma.csv", "--free",
        "impulses.0.delta_v.1")
refused("--free 'bodies.dimorphos.shape'", "--observations", "observed.csv", "--free", "bodies.dimorphos.shape")
refused("--free 'G': G follows from the scene's declared units", "--observations", "observed.csv", "--free", "G")
with open("before.csv", "w") as f:  # all before the impact: they cannot see its Δv
    f.write("t,observable,target,center,value,sigma\n3600,range,dimorphos,didymos,1200,1\n7200,range,dimorphos,didymos,1200,1\n")
refused("the observations do not depend on impulses.0.delta_v.1", "--observations", "before.csv", "--free",
        "impulses.0.delta_v.1")
print("refused by name: an observation before the run, an unknown body, a zero sigma, keys that cannot be varied, "
      "a parameter the data do not see")

# From mutual-event times (docs/fitting.md): the conjunctions on the sky before and after the
# impact, 30 s each; Δv and Didymos' density within 3σ of the truth, each event time's
# derivative (30.2) against whole runs at Δv ± 1e-5 m/s (its column of the fit's Jacobian
# reproduces the change of the computed times).
noether_run("observe", "truth.h5", "--observable", "conjunction.time:dimorphos:didymos", "--line-of-sight",
            "-1,0,-0.1", "--sigma", "30", "--noise", "--seed", "5", "-o", "events.csv", "--force")
events = noether_run("fit", scene, "--observations", "events.csv", "--free",
                     "impulses.0.delta_v.1,bodies.didymos.density", "-o", "events-fit.json", "--force")
fit = json.load(open("events-fit.json"))
p = {x["name"]: x for x in fit["parameters"]}
dv, rho = p["impulses.0.delta_v.1"], p["bodies.didymos.density"]
assert fit["converged"] and fit["observations"] == 12, fit["stop"]
assert abs(dv["estimate"] - truth) < 3 * dv["sigma"] and abs(rho["estimate"] - 2203.111036687207) < 3 * rho["sigma"]
print(f"from 12 event times: Δv = {dv['estimate'] * 1e3:.4f} ± {dv['sigma'] * 1e3:.4f} mm/s, Didymos' density "
      f"{rho['estimate']:.3f} ± {rho['sigma']:.3f} kg/m³")
times = {}
for d in (-1e-5, 1e-5):
    noether_run("run", scene, "--no-progress", "--force", "--set", f"impulses.0.delta_v.1={truth + d}", "-o", "dv.h5")
    rows = noether_run("observe", "dv.h5", "--at", "events.csv").stdout.splitlines()
    times[d] = np.array([float(l.split(",")[4]) for l in rows if l and l[0].isdigit()])
slope = (times[1e-5] - times[-1e-5]) / 2e-5
noether_run("fit", scene, "--observations", "events.csv", "--free", "impulses.0.delta_v.1", "-o", "dv-fit.json", "--force")
single = json.load(open("dv-fit.json"))["parameters"][0]
# A linear least squares of one parameter: σ = σ_t / √Σ (dt/dΔv)² — from the whole runs' slopes.
assert abs(30 / np.sqrt(np.sum(slope ** 2)) / single["sigma"] - 1) < 1e-4, (30 / np.sqrt(np.sum(slope ** 2)), single)
print(f"Δv alone: σ {single['sigma'] * 1e3:.5f} mm/s; from whole runs' event-time slopes {30e3 / np.sqrt(np.sum(slope ** 2)):.5f}")

# A fit to runs that cannot be trusted says so (stdout, stderr, JSON), though it converges: here
# the energy threshold is set below what any run meets.
untrusted = noether_run("fit", scene, "--observations", "events.csv", "--free", "impulses.0.delta_v.1", "--set",
                        "run.trust.energy=1e-16", "-o", "untrusted.json", "--force")
assert "verdict               UNTRUSTWORTHY (the run at the estimate): relative energy error" in untrusted.stdout
assert "noether: UNTRUSTWORTHY FIT" in untrusted.stderr, untrusted.stderr
bad = json.load(open("untrusted.json"))
assert bad["converged"] and not bad["trustworthy"] and "relative energy error" in bad["verdict"][0], bad["verdict"]
assert json.load(open("dv-fit.json"))["trustworthy"] is True
print("an untrustworthy run at the estimate: said on stdout, stderr and in the JSON")
