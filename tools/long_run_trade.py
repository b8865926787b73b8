#!/usr/bin/python3
"""The long-run trade between a symplectic method and adaptive baselines: for each run length T,
every integrator's max |E − E0| and wall time, and for each LGVI setting the cheapest baseline
that reaches the same energy error (log-log interpolation along each baseline's tolerance
sweep), so the crossover T — where the LGVI becomes the cheaper way to a given energy error — can
be read off.

    tools/long_run_trade.py SCENE --t-end T1,T2,... [--noether PATH] [--frames N] [--budget S]
                            [--json OUT.json] [--plot OUT.png]
    tools/long_run_trade.py --replot IN.json --plot OUT.png   (a plot from saved measurements)

Each run is `noether run SCENE --set run.t_end=T --set run.output_every=T/N --summary json`
(N = 2000 frames by default) with a wall-time budget of S seconds (default 600); a run that
exhausts it is reported as such. The integrators are the LGVI at order 2 and 4 (Suzuki's
composition) at the scene's step, and dopri5 and CVODE Adams over a tolerance sweep.
"""
import argparse
import json
import math
import os
import subprocess
import sys

SYMPLECTIC = [("lgvi", "{plugin: lgvi, step: %(h)s}"),
              ("lgvi suzuki-4", "{plugin: lgvi, order: 4, composition: suzuki, step: %(h4)s}")]
BASELINES = [("dopri5", "{plugin: rk, method: dopri5, rtol: %(r)g, atol: %(a)g}", [1e-7, 1e-8, 1e-9, 1e-10, 1e-11]),
             ("cvode adams", "{plugin: cvode, method: adams, rtol: %(r)g, atol: %(a)g}", [1e-8, 1e-9, 1e-10, 1e-11])]


def run(noether, scene, t_end, frames, integrator, budget):
    cmd = [noether, "run", scene, "--no-progress", "--summary", "json", "--max-wall-time", str(budget),
           "--set", f"run.t_end={t_end!r}", "--set", f"run.output_every={t_end / frames!r}",
           "--set", "integrator=" + integrator]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        return {"failed": (p.stderr.strip().splitlines() or ["exit %d" % p.returncode])[-1]}
    s = json.loads(p.stdout)
    return {"energy": s["max_abs_energy_error"], "wall": s["wall_seconds"], "evals": s["potential_evaluations"],
            "stopped": s["stop_reason"]}


def interpolate_cost(points, target):
    """Wall time at which a sweep [(error, wall)] reaches `target` (log-log between neighbours);
    None when no run of the sweep is that accurate."""
    pts = sorted((e, w) for e, w in points if e > 0 and w > 0)
    if not pts or pts[0][0] > target:
        return None
    for (e0, w0), (e1, w1) in zip(pts, pts[1:]):
        if e0 <= target <= e1:
            f = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(w0) + f * (math.log(w1) - math.log(w0)))
    return min(w for e, w in pts if e <= target)  # every run more accurate: the cheapest


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene", nargs="?")
    ap.add_argument("--t-end", help="comma-separated run lengths")
    ap.add_argument("--noether", default=os.path.join(os.path.dirname(__file__), "..", "build", "release", "bin", "noether"))
    ap.add_argument("--frames", type=int, default=2000)
    ap.add_argument("--budget", type=float, default=600.0)
    ap.add_argument("--step", type=float, default=2e-3, help="LGVI order-2 step (order 4 uses 5x)")
    ap.add_argument("--json", help="write every measurement here")
    ap.add_argument("--plot", help="draw the cost of each method at the LGVI's energy error against T")
    ap.add_argument("--replot", nargs="+", help="saved --json files to plot (no runs)")
    a = ap.parse_args()
    if a.replot:
        results = {}
        for path in a.replot:
            with open(path) as f:
                results.update({float(t): rows for t, rows in json.load(f).items()})
        plot(results, a.plot)
        return 0
    if not a.scene or not a.t_end:
        ap.error("SCENE and --t-end are required (or --replot)")
    results = {}
    for t_end in [float(t) for t in a.t_end.split(",")]:
        print(f"T = {t_end:g}", flush=True)
        rows = {}
        for name, spec in SYMPLECTIC:
            rows[name] = run(a.noether, a.scene, t_end, a.frames, spec % {"h": repr(a.step), "h4": repr(5 * a.step)}, a.budget)
        for family, spec, rtols in BASELINES:
            for r in rtols:
                rows[f"{family} rtol {r:g}"] = run(a.noether, a.scene, t_end, a.frames, spec % {"r": r, "a": r * 1e-2}, a.budget)
        for name, m in rows.items():
            if "failed" in m:
                print(f"  {name:24s} failed: {m['failed']}")
            else:
                note = f"  stopped: {m['stopped']}" if m["stopped"] else ""
                print(f"  {name:24s} max|dE| {m['energy']:.2e}  wall {m['wall']:8.3f} s  evals {m['evals']:>11}{note}")
        for name, _ in SYMPLECTIC:
            m = rows[name]
            if "failed" in m or m["stopped"]:
                continue
            for family, _, rtols in BASELINES:
                sweep = [(rows[f"{family} rtol {r:g}"]["energy"], rows[f"{family} rtol {r:g}"]["wall"]) for r in rtols
                         if "failed" not in rows[f"{family} rtol {r:g}"] and not rows[f"{family} rtol {r:g}"]["stopped"]]
                cost = interpolate_cost(sweep, m["energy"])
                verdict = "no run of the sweep is that accurate" if cost is None else \
                    f"{cost:.3f} s: the {'baseline' if cost < m['wall'] else 'LGVI'} is cheaper by {max(cost, m['wall']) / min(cost, m['wall']):.2f}x"
                print(f"  equal max|dE| {m['energy']:.2e}: {name} {m['wall']:.3f} s, {family} {verdict}")
        results[t_end] = rows
    if a.json:
        with open(a.json, "w") as f:
            json.dump(results, f, indent=1)
    if a.plot:
        plot(results, a.plot)
    return 0


def plot(results, png):
    """Wall time against T: each LGVI setting, and each baseline at that setting's max |dE|."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 5))
    ts = sorted(results)
    for (name, _), colour in zip(SYMPLECTIC, ["C0", "C1"]):
        own = [(t, results[t][name]) for t in ts if name in results[t] and "failed" not in results[t][name]]
        ax.loglog([t for t, _ in own], [m["wall"] for _, m in own], "o-", color=colour,
                  label=f"{name} (|dE| ~ {own[-1][1]['energy']:.0e})" if own else name)
        for (family, _, rtols), style in zip(BASELINES, ["s--", "^:"]):
            pts = []
            for t, m in own:
                sweep = [(results[t][k]["energy"], results[t][k]["wall"]) for k in (f"{family} rtol {r:g}" for r in rtols)
                         if k in results[t] and "failed" not in results[t][k] and not results[t][k]["stopped"]]
                cost = interpolate_cost(sweep, m["energy"])
                if cost is not None:
                    pts.append((t, cost))
            if pts:
                ax.loglog([t for t, _ in pts], [c for _, c in pts], style, color=colour, alpha=0.7,
                          label=f"{family} at the {name}'s |dE|")
    ax.set_xlabel("run length T [scene time units]")
    ax.set_ylabel("wall time [s]")
    ax.set_title("equal energy error: cost against run length", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=90)


if __name__ == "__main__":
    sys.exit(main())
