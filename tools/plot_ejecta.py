#!/usr/bin/python3
"""Draws what became of a run's massless particles (docs/user-guide.md, "Particles"): left, the
fraction of the cloud landed on each body, escaped and still in flight against time; right, each
fate against the launch speed relative to the surface the particles left (an ejecta cloud,
docs/equations.md §39; the launch body is the one whose surface is nearest the first particle's
start). Prints the final fractions.

    tools/plot_ejecta.py RUN.h5 OUT.png [--title T]

Exits 2 when the run holds no /test_particles (a run without particles, or one that was killed).
"""
import argparse
import sys

from plot_common import pyplot

plt, h5py, np = pyplot(__file__, "h5py", "numpy")
from plot_libration import rotation  # noqa: E402  (a quaternion's matrix; this script's folder is on the path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run")
    ap.add_argument("out")
    ap.add_argument("--title", default=None)
    a = ap.parse_args()
    with h5py.File(a.run, "r") as f:
        if "test_particles" not in f:
            sys.stderr.write(f"{a.run}: no /test_particles (a run without particles, or one that did not finish)\n")
            return 2
        t = f["test_particles"]
        x0, v0 = t["initial_position"][...], t["initial_velocity"][...]
        fate, body, when = t["fate"][...], t["body"][...], t["time"][...]
        text = lambda v: v.decode() if isinstance(v, bytes) else str(v)  # noqa: E731
        names = [text(n) for n in f["particles/bodies/name"][:]]
        pos = f["particles/bodies/position/value"][0]
        vel = f["particles/bodies/velocity/value"][0]
        times = f["particles/bodies/position/time"][:]
        orient = f["particles/bodies/orientation"]
        q = orient["value"][0]
        index = list(orient.attrs["body_index"]) if "body_index" in orient.attrs else list(range(len(q)))
        omega = f["particles/bodies/angular_velocity/value"][0] if "particles/bodies/angular_velocity" in f else None
    n = len(fate)
    # The body the cloud left: its centre nearest the first particle's start.
    b = int(np.argmin(np.linalg.norm(pos - x0[0], axis=1)))
    v_rel = v0 - vel[b]
    if omega is not None and b in index:  # Ω is body-frame, one row per rigid body (body_index)
        k = index.index(b)
        v_rel = v_rel - np.cross(rotation(q[k]) @ omega[k], x0 - pos[b])
    speed = np.linalg.norm(v_rel, axis=1)

    classes = [(f"landed on {nm}", (fate == 1) & (body == k)) for k, nm in enumerate(names)]
    classes += [("escaped", fate == 2), ("in flight", fate == 0)]
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    grid = np.linspace(0, times[-1], 400)
    for label, m in classes:
        if label == "in flight":
            done = np.sum([np.sum(mm[:, None] & (when[:, None] <= grid[None, :]), axis=0)
                           for lb, mm in classes if lb != "in flight"], axis=0)
            left.plot(grid / 3600, 1 - done / n, label=label)
        else:
            left.plot(grid / 3600, np.sum(m[:, None] & (when[:, None] <= grid[None, :]), axis=0) / n, label=label)
        print(f"{label:28s} {np.sum(m):7d}  {np.sum(m) / n:.4f}")
    left.set_xlabel("time (h)")
    left.set_ylabel(f"fraction of the {n} particles")
    left.legend()
    left.grid(alpha=0.3)
    bins = np.geomspace(speed.min(), speed.max() * (1 + 1e-12), 25)
    right.hist([speed[m] for _, m in classes], bins=bins, stacked=True, label=[lb for lb, _ in classes])
    right.set_xscale("log")
    right.set_xlabel(f"launch speed relative to {names[b]}'s surface (scene units / s)")
    right.set_ylabel("particles")
    right.legend(fontsize=8)
    fig.suptitle(a.title or f"{a.run}: {n} particles")
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
