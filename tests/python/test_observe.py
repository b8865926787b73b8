"""noether.observe (docs/fitting.md): the same numbers as `noether observe` and as the file's own
positions, interpolated between frames, refused by name."""
import subprocess

import numpy as np
import pytest

import noether


def test_observe_agrees_with_the_command_and_the_file(source, noether_exe, tmp_path):
    run = tmp_path / "d.h5"
    subprocess.run([noether_exe, "run", str(source / "examples/didymos.yaml"), "--no-progress", "--set",
                    "run.t_end=7200", "--set", "run.output_every=600", "-o", str(run)], check=True,
                   stdout=subprocess.DEVNULL)
    t, rho = noether.observe(run, "range:dimorphos:didymos")
    out = noether.read(run)
    r = out["positions"][:, 1] - out["positions"][:, 0]
    assert np.array_equal(t, out["time"])
    assert np.max(np.abs(rho - np.linalg.norm(r, axis=1))) < 1e-12 * 1200
    # The command writes the same numbers (to 17 digits).
    text = subprocess.run([noether_exe, "observe", str(run), "--observable", "range:dimorphos:didymos"],
                          check=True, capture_output=True, text=True).stdout
    values = [float(line.split(",")[4]) for line in text.splitlines()[2:]]
    assert values == list(rho)
    # Between frames: the interpolant (eq. 16.2) against a run with a frame there, within the
    # estimate r ω⁴ Δ⁴ / 384 = 1.9e-4 m for frames 600 s apart (docs/fitting.md); at a frame's
    # time, the frame's value.
    fine = tmp_path / "fine.h5"
    subprocess.run([noether_exe, "run", str(source / "examples/didymos.yaml"), "--no-progress", "--set",
                    "run.t_end=7200", "--set", "run.output_every=300", "-o", str(fine)], check=True,
                   stdout=subprocess.DEVNULL)
    _, between = noether.observe(run, "range:dimorphos:didymos", times=[600.0, 900.0, 4500.0])
    _, on_frames = noether.observe(fine, "range:dimorphos:didymos", times=[600.0, 900.0, 4500.0])
    assert between[0] == rho[1]
    assert 1e-7 < np.max(np.abs(between - on_frames)) < 2.5e-4
    _, east = noether.observe(run, "sky.east:dimorphos:didymos", line_of_sight=[1, 0, 0])
    assert np.max(np.abs(east - r[:, 1])) < 1e-12 * 1200  # looking along +x, east is +y
    with pytest.raises(noether.SceneError, match="outside the run"):
        noether.observe(run, "range:dimorphos:didymos", times=[7300.0])
    with pytest.raises(noether.SceneError, match="no body 'dimorphus'.*did you mean dimorphos"):
        noether.observe(run, "range:dimorphus:didymos")
    with pytest.raises(noether.SceneError, match="needs a line of sight"):
        noether.observe(run, "sky.north:dimorphos:didymos")
    # A lightcurve: the command's numbers; the pair's brightness the sum of its bodies' outside
    # the mutual events (the line of sight along x: Dimorphos is in front of Didymos at t = 0).
    views = dict(line_of_sight=[-1, 0, 0], sunlight=[-1, -0.3, 0])
    t, pair = noether.observe(run, "lightcurve.lommel_seeliger:dimorphos:didymos", **views)
    text = subprocess.run([noether_exe, "observe", str(run), "--observable",
                           "lightcurve.lommel_seeliger:dimorphos:didymos", "--line-of-sight", "-1,0,0", "--sunlight",
                           "-1,-0.3,0"], check=True, capture_output=True, text=True).stdout
    assert [float(line.split(",")[4]) for line in text.splitlines()[2:]] == list(pair)
    _, primary = noether.observe(run, "lightcurve.lommel_seeliger:didymos:didymos", **views)
    _, secondary = noether.observe(run, "lightcurve.lommel_seeliger:dimorphos:dimorphos", **views)
    depth = 1 - pair / (primary + secondary)
    assert depth[0] > 0.03 and np.all(depth > -1e-12) and np.any(np.abs(depth) < 1e-12)
    # Conjunctions: every one in the run, each its own nearest; the projected separation least there.
    t_events, events = noether.observe(run, "conjunction.time:dimorphos:didymos",
                                       line_of_sight=[-0.8645, -0.5026, -0.1])
    assert len(events) == 1 and np.array_equal(t_events, events) and 3000 < events[0] < 4000
    _, again = noether.observe(run, "conjunction.time:dimorphos:didymos", times=[events[0] - 1000],
                               line_of_sight=[-0.8645, -0.5026, -0.1])
    assert again[0] == events[0]
    with pytest.raises(noether.SceneError, match="needs the sunlight's direction"):
        noether.observe(run, "lightcurve.lambert:dimorphos:didymos", line_of_sight=[1, 0, 0])


def test_fit_is_the_commands(source, noether_exe, tmp_path):
    """noether.fit gives the command's fit (the same numbers in its JSON), arrays by name."""
    import json
    scene = str(source / "examples/didymos-dart.yaml")
    subprocess.run([noether_exe, "run", scene, "--no-progress", "--set", "impulses.0.delta_v.1=-0.0027",
                    "-o", str(tmp_path / "truth.h5")], check=True, stdout=subprocess.DEVNULL)
    subprocess.run([noether_exe, "observe", str(tmp_path / "truth.h5"), "--at",
                    str(source / "examples/observations/dart-epochs.csv"), "--noise", "--seed", "3", "-o",
                    str(tmp_path / "obs.csv")], check=True, capture_output=True)
    subprocess.run([noether_exe, "fit", scene, "--observations", str(tmp_path / "obs.csv"), "--free",
                    "impulses.0.delta_v.1", "-o", str(tmp_path / "fit.json")], check=True, stdout=subprocess.DEVNULL)
    command = json.load(open(tmp_path / "fit.json"))
    fit = noether.fit(scene, tmp_path / "obs.csv", ["impulses.0.delta_v.1"])
    assert fit["names"] == ["impulses.0.delta_v.1"] and fit["converged"]
    assert fit["estimate"][0] == command["parameters"][0]["estimate"]
    assert fit["sigma"][0] == command["parameters"][0]["sigma"]
    assert fit["covariance"].shape == (1, 1) and fit["chi2"] == command["chi2"]
    assert abs(fit["estimate"][0] + 0.0027) < 3 * fit["sigma"][0]
    with pytest.raises(noether.SceneError, match="--free 'bodies.dimorphos.colour'"):
        noether.fit(scene, tmp_path / "obs.csv", "bodies.dimorphos.colour")
