#!/usr/bin/python3
"""Measures and draws a rigid body's libration in a noether run (HDF5): the angle, about the
total angular momentum, between the body's long axis (its least principal moment) and the line
to another body, against time; its amplitude and its period from the upward zero crossings.

    tools/plot_libration.py RUN.h5 OUT.png --body NAME [--other NAME] [--expect PERIOD] [--title T]

--other defaults to the first other body. --expect (e.g. the libration period that
`noether orbit equilibrium` prints) is drawn as a reference sinusoid and compared. The angle is
folded into (−90°, 90°]: the long axis has no sign. Exits 1 when the run holds fewer than two
upward crossings (run longer), 2 for a body that is not rigid or not in the run.
"""
import argparse
import math
import sys

from plot_common import labelled, pyplot, save, unit_of

plt, h5py, np = pyplot(__file__, "h5py", "numpy")


def rotation(q):
    """The matrix of a unit quaternion (w, x, y, z)."""
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def libration_angle(f, body, other):
    text = lambda v: v.decode() if isinstance(v, bytes) else str(v)  # noqa: E731
    names = [text(n) for n in f["particles/bodies/name"][:]]
    for n in (body, other):
        if n not in names:
            sys.stderr.write(f"plot_libration.py: no body '{n}' in the run (bodies: {', '.join(names)})\n")
            sys.exit(2)
    i, j = names.index(body), names.index(other)
    frames = int(f["frames_complete"][()])  # a killed run: only its complete frames
    rigid = list(f["particles/bodies/orientation"].attrs["body_index"])
    if i not in rigid:
        sys.stderr.write(f"plot_libration.py: body '{body}' is not rigid: it has no attitude to librate\n")
        sys.exit(2)
    r = rigid.index(i)
    inertia = f["particles/bodies/inertia"][r]
    axis = np.linalg.eigh(inertia)[1][:, 0]  # the long axis: least moment
    q = f["particles/bodies/orientation/value"][:frames, r, :]
    x = f["particles/bodies/position/value"][:frames]
    t = f["observables/energy/time"][:frames]
    t_unit = unit_of(f["observables/energy/time"])
    L = f["observables/angular_momentum/value"][0]
    k = L / np.linalg.norm(L)
    angle = np.empty(frames)
    for n in range(frames):
        a = rotation(q[n]) @ axis
        line = x[n, j] - x[n, i]
        a, line = a - k * (k @ a), line - k * (k @ line)
        theta = math.atan2(np.cross(line, a) @ k, line @ a)
        angle[n] = (theta + math.pi / 2) % math.pi - math.pi / 2  # the long axis has no sign
    return t, t_unit, angle, names[j]


def upward_crossings(t, y):
    return [t[n - 1] + (t[n] - t[n - 1]) * (-y[n - 1]) / (y[n] - y[n - 1])
            for n in range(1, len(y)) if y[n - 1] < 0 <= y[n]]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run")
    ap.add_argument("png")
    ap.add_argument("--body", required=True)
    ap.add_argument("--other", default=None)
    ap.add_argument("--expect", type=float, default=None, help="a predicted libration period, to compare")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    with h5py.File(a.run, "r") as f:
        if a.other is None:
            names = [n.decode() if isinstance(n, bytes) else str(n) for n in f["particles/bodies/name"][:]]
            a.other = next((n for n in names if n != a.body), a.body)
        t, t_unit, angle, other = libration_angle(f, a.body, a.other)
    up = upward_crossings(t, angle)
    amplitude = float(np.max(np.abs(angle)))
    print(f"libration of {a.body} about the line to {other}, {len(t)} frames")
    print(f"amplitude                        {amplitude:.6f} rad")
    period = None
    if len(up) >= 2:
        period = (up[-1] - up[0]) / (len(up) - 1)
        print(f"period (zero crossings)          {period:.6g} {t_unit} ({len(up) - 1} cycles)")
    if a.expect:
        print(f"period expected                  {a.expect:.6g} {t_unit}")
        if period:
            print(f"relative difference              {period / a.expect - 1:.2e}")
    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.plot(t, np.degrees(angle), lw=1, label=f"{a.body}: long axis − line to {other}")
    if a.expect and up:
        ref = amplitude * np.sin(2 * math.pi * (t - up[0]) / a.expect)
        ax.plot(t, np.degrees(ref), "--", lw=0.8, color="0.4", label=f"linearisation: period {a.expect:.6g}")
    ax.axhline(0, color="0.7", lw=0.5)
    ax.set_xlabel(labelled("t", t_unit))
    ax.set_ylabel("libration angle [deg]")
    ax.legend(fontsize=7, loc="upper right")
    ax.set_title(a.title or f"{a.run}", fontsize=8)
    fig.tight_layout()
    save(fig, a.png)
    print(f"plot: {a.png}")
    if period is None:
        sys.stderr.write("plot_libration.py: fewer than two upward zero crossings: run longer to measure a period\n")
        sys.exit(1)


if __name__ == "__main__":
    main()
