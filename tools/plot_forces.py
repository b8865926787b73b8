#!/usr/bin/python3
"""Draws what the forces beyond the potential did in a noether run (HDF5; docs/forces.md): a rigid
body's spin rate, the binary's osculating semi-major axis and eccentricity, and the energy
balance — the work W each force did, and E − ΣW − E0, what the forced flow conserves (its error
is the integrator's; docs/equations.md eq. 33.3) — against time.

    tools/plot_forces.py RUN.h5 OUT.png [--body NAME] [--title T]

--body: the rigid body whose spin is drawn (default: the first rigid body). Exits 2 for a run
without forces: or without rigid bodies.
"""
import argparse
import sys

from plot_common import labelled, pyplot, save, unit_of

plt, h5py, np = pyplot(__file__, "h5py", "numpy")


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("run")
    p.add_argument("png")
    p.add_argument("--body")
    p.add_argument("--title", default="")
    a = p.parse_args()
    with h5py.File(a.run, "r") as f:
        if "observables/force_balance" not in f:
            sys.stderr.write(f"plot_forces.py: {a.run} has no forces (no /observables/force_balance)\n")
            return 2
        names = [text(n) for n in f["particles/bodies/name"][:]]
        forces = text(f["parameters"].attrs["forces"]).split("\n")
        t = f["particles/bodies/position/time"][:]
        t_unit = unit_of(f["particles/bodies/position/time"])
        e_unit = unit_of(f["observables/energy/value"])
        balance = f["observables/force_balance/value"][:]  # [frame][force][7]
        E = f["observables/energy/value"][:]
        if "particles/bodies/angular_velocity" not in f:
            sys.stderr.write("plot_forces.py: the run has no rigid body\n")
            return 2
        rigid = [names[i] for i in f["particles/bodies/inertia"].attrs["body_index"]]
        omega = f["particles/bodies/angular_velocity/value"][:]  # [frame][rigid][3]
        omega_unit = unit_of(f["particles/bodies/angular_velocity/value"])
        elements = f["observables/osculating_elements/value"][:] if "observables/osculating_elements" in f else None
        a_unit = unit_of(f["observables/separation/value"]) if "observables/separation" in f else ""
    k = 0
    if a.body:
        if a.body not in rigid:
            sys.stderr.write(f"plot_forces.py: no rigid body '{a.body}' in the run\n")
            return 2
        k = rigid.index(a.body)
    body = a.body or rigid[0]
    spin = np.linalg.norm(omega[:, k, :], axis=1)
    W = balance[:, :, 0]
    drift = E - W.sum(axis=1) - E[0]
    print(f"forces                           {', '.join(forces)}")
    print(f"spin rate of {body:<19} {spin[0]:.6g} -> {spin[-1]:.6g} (relative change {spin[-1] / spin[0] - 1:+.3e})")
    if elements is not None:
        print(f"semi-major axis                  {elements[0, 0]:.6g} -> {elements[-1, 0]:.6g}")
        print(f"eccentricity                     {elements[0, 1]:.6g} -> {elements[-1, 1]:.6g}")
    print(f"work                             {W[-1].sum():.6g}")
    print(f"max |E - W - E0|                 {np.abs(drift).max():.3e}")

    rows = 3 if elements is not None else 2
    fig, ax = plt.subplots(rows, 1, figsize=(7, 2.4 * rows), sharex=True)
    ax[0].plot(t, spin, "C0")
    ax[0].set_ylabel(labelled(f"|ω| of {body}", omega_unit))
    if elements is not None:
        ax[1].plot(t, elements[:, 0], "C1", label="a")
        ax[1].set_ylabel(labelled("semi-major axis a", a_unit), color="C1")
        twin = ax[1].twinx()
        twin.plot(t, elements[:, 1], "C2")
        twin.set_ylabel("eccentricity e", color="C2")
    last = ax[-1]
    for j, name in enumerate(forces):
        last.plot(t, W[:, j], label=f"W, {name}")
    last.plot(t, drift, "k", lw=0.8, label="E − ΣW − E0")
    last.set_ylabel(labelled("energy", e_unit))
    last.set_xlabel(labelled("t", t_unit))
    last.legend(fontsize=8)
    if a.title:
        ax[0].set_title(a.title)
    fig.tight_layout()
    save(fig, a.png)
    print(f"plot: {a.png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
