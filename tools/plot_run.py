#!/usr/bin/python3
"""Plots a noether run (HDF5): energy exchange, energy error and, with rigid bodies, ‖I − RᵀR‖
against time, in the run's units.

    tools/plot_run.py RUN.h5 OUT.png [--title TITLE]

Uses Debian's python3-matplotlib and python3-h5py (installed by tools/install-deps.sh).
"""
import argparse
import os

from plot_common import labelled, pyplot, unit_of

plt, h5py = pyplot(__file__, "h5py")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run")
    ap.add_argument("png")
    ap.add_argument("--title", default=None)
    args = ap.parse_args()
    with h5py.File(args.run, "r") as f:
        obs = f["observables"]
        t = obs["energy/time"][:]
        E = obs["energy/value"][:]
        T_tr = obs["kinetic_energy_translational/value"][:]
        T_rot = obs["kinetic_energy_rotational/value"][:]
        U = obs["potential_energy/value"][:]
        orth = obs["orthogonality_error/value"][:]
        rigid = "orientation" in f["particles/bodies"]
        text = lambda v: v.decode() if isinstance(v, bytes) else str(v)  # noqa: E731
        integrator = text(f["parameters"].attrs["integrator"])
        e_unit = unit_of(obs["energy/value"])
        t_unit = unit_of(obs["energy/time"])
    fig, ax = plt.subplots(3 if rigid else 2, 1, figsize=(7, 8 if rigid else 5.5), sharex=True)
    ax[0].plot(t, T_tr, label="translational kinetic")
    ax[0].plot(t, T_rot, label="rotational kinetic")
    ax[0].plot(t, U, label="potential")
    ax[0].set_ylabel(labelled("energy", e_unit))
    ax[0].legend(fontsize=8)
    ax[1].plot(t, E - E[0])
    ax[1].set_ylabel(labelled("E − E0", e_unit))
    if rigid:
        ax[2].semilogy(t, orth + 1e-18)
        ax[2].set_ylabel("‖I − RᵀR‖_F")
    ax[-1].set_xlabel(labelled("t", t_unit))
    fig.suptitle(args.title or f"{os.path.basename(args.run)} ({integrator})")
    fig.tight_layout()
    fig.savefig(args.png, dpi=90)


if __name__ == "__main__":
    main()
