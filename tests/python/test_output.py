"""Output files from Python: the reader, compare's table, and runs killed and resumed."""
import os
import random
import signal
import subprocess
import sys
import textwrap
import time

import h5py
import numpy as np
import pytest

import noether


def test_the_reader_gives_named_arrays_with_units(source, tmp_path):
    sim = noether.Simulation(source / "examples/kw4-elements.yaml", output=tmp_path / "kw4.h5",
                             set=["run.t_end=36000", "run.output_every=3600"])
    sim.integrate(sim.run["t_end"])
    summary = sim.finish()
    out = noether.read(tmp_path / "kw4.h5")
    assert out.frames == summary["output_frames"] == 11
    assert out.outcome == "completed"
    assert out["positions"].shape == (11, len(out.names), 3)
    assert out.unit("positions") == sim.units["length"]
    assert out.unit("time") == sim.units["time"]
    assert out["time"][-1] == 36000
    # The exact state: the last frame is the simulation's final state, bit for bit.
    assert out["positions"][-1].tobytes() == sim.positions.tobytes()
    assert out["momenta"][-1].tobytes() == sim.momenta.tobytes()
    assert out["attitudes"][-1].tobytes() == sim.attitudes.tobytes()
    assert np.abs(out.energy_error()).max() == pytest.approx(summary["max_abs_energy_error"], rel=1e-12)
    with pytest.raises(KeyError, match="this file has"):
        out["nonsense"]


def _frame_series(f):
    """Every dataset of an output file with one entry per frame (the series), except the checksums."""
    n = f["frames_complete"][()]
    not_series = {"particles/bodies/name", "particles/bodies/mass", "particles/bodies/inertia", "checkpoint/checksum"}
    found = {}

    def visit(path, obj):
        if (isinstance(obj, h5py.Dataset) and obj.shape and obj.shape[0] == n and path not in not_series
                and path.split("/")[0] in ("particles", "observables", "checkpoint")):
            found[path] = obj
    f.visititems(visit)  # visits each object once, under one of its names: step and time are links
    return {p: d for p, d in found.items() if p.split("/")[-1] not in ("step", "time")}


@pytest.mark.parametrize("scene,overrides,has", [
    ("dumbbells.yaml", ["integrator.step=0.001"],
     {"rigid bodies", "a binary", "a binary with a rigid primary", "a binary with a rigid secondary",
      "an integrator with variables of its own"}),
    ("dumbbells.yaml", ["integrator.step=0.001", "integrator.frame=relative"],
     {"rigid bodies", "a binary", "a binary with a rigid primary", "a binary with a rigid secondary",
      "an integrator with variables of its own"}),
    ("figure-eight.yaml", ["integrator.plugin=rk", "integrator.method=rk4", "integrator.step=0.001"],
     {"an integrator with variables of its own"}),  # rk4's clock
    ("figure-eight.yaml", ["integrator.plugin=rk", "integrator.method=dopri5"], set()),
    ("didymos-spacecraft.yaml", ["integrator.step=0.01", "run.output_every=0.01"],
     {"rigid bodies", "a binary", "a binary with a rigid primary", "a binary with a rigid secondary",
      "an integrator with variables of its own"}),
    ("didymos-particles.yaml", ["integrator.step=0.01", "run.output_every=0.01", "particles.record=3"],
     {"rigid bodies", "a binary", "a binary with a rigid primary", "a binary with a rigid secondary", "particles",
      "an integrator with variables of its own"})])
def test_the_files_series_are_the_schema_table(source, tmp_path, scene, overrides, has):
    """The writer, the reader and noether.output_series() are one table: a file holds exactly
    the schema's series (the rigid bodies' only with rigid bodies, the integrator's own only when
    it has variables), each with the schema's type, rank, unit and description."""
    out = tmp_path / "run.h5"
    sim = noether.Simulation(source / "examples" / scene, output=out,
                             set=overrides + ["run.t_end=0.05", "run.output_every=0.01"])
    sim.integrate(sim.run["t_end"])
    sim.finish()
    schema = {s["path"].lstrip("/"): s for s in noether.output_series()}
    expected = {p for p, s in schema.items() if s["needs"] in has | {""}}
    with h5py.File(out, "r") as f:
        frames = _frame_series(f)
        assert set(frames) == {p for p in expected if p.split("/")[-1] not in ("step", "time")}
        for path in frames:  # every H5MD element's step and time: the position's, hard-linked
            if path.endswith("/value"):
                element = path[: -len("/value")]
                for link in ("step", "time"):
                    assert f[element + "/" + link] == f["particles/bodies/position/" + link], element
        for path in expected:
            d, s = f[path], schema[path]
            assert d.attrs["description"] == s["description"]
            assert d.dtype == (np.int64 if s["integer"] else np.float64)
            assert d.ndim == s["shape"].count("["), path
            if "L" not in s["unit"] and "M" not in s["unit"] and "T" not in s["unit"]:
                assert d.attrs["unit"] == s["unit"], path  # the scene-independent units
        assert sorted(f["checkpoint/checksum"].attrs["columns"].split("\n")) == sorted(
            "/" + p for p, s in schema.items() if s["checkpointed"])
    reader = noether.read(out)
    assert set(reader.keys()) == {schema[p]["name"] for p in expected}


def test_the_particles_are_read_with_their_fates(source, tmp_path):
    """A run with massless particles: the reader's particle_positions hold the recorded ones at
    every frame, ending where /test_particles says each one ended (docs/user-guide.md, "Particles")."""
    out = tmp_path / "particles.h5"
    sim = noether.Simulation(source / "examples" / "didymos-particles.yaml", output=out,
                             set=["run.t_end=3600", "run.output_every=600", "particles.record=5"])
    sim.integrate(sim.run["t_end"])
    live = sim.particles  # where the run stands: what /test_particles is written from
    sim.finish()
    run = noether.read(out)
    p = run.particles
    assert set(live) == set(p), (set(live), set(p))
    for key, value in live.items():
        if key in ("fields", "surfaces"):
            assert value == p[key]
        else:  # NaN: the time of a particle still in flight
            np.testing.assert_array_equal(value, p[key], err_msg=key)
    assert noether.Simulation(source / "examples" / "dumbbells.yaml").particles is None
    assert p["fate"].shape == (24,) and set(p["fate"]) <= {0, 1, 2}
    assert len(p["fields"]) == 2 and p["fields"][1].startswith("exact (ellipsoid")
    track = run["particle_positions"]
    assert track.shape == (7, 5, 3)
    np.testing.assert_array_equal(track[0], p["initial_position"][:5])
    landed = p["fate"] == 1
    flying = ~landed[:5]
    np.testing.assert_array_equal(track[-1][flying], p["position"][:5][flying])
    for i in np.flatnonzero(landed[:5]):  # rides on its body: as far from its centre as where it landed
        centre = run["positions"][-1][p["body"][i]]
        assert abs(np.linalg.norm(track[-1][i] - centre) - np.linalg.norm(p["impact_point"][i])) < 1e-9
    assert np.all(p["body"][landed] >= 0) and np.all(p["body"][~landed & (p["fate"] == 0)] == -1)
    assert np.all(np.isnan(p["time"][p["fate"] == 0]))


def test_the_user_guide_names_every_series(source):
    """docs/user-guide.md's layout names every series of the schema: an H5MD element by its
    group (`/particles/bodies/velocity/{...}`, or its name in the /observables list), a plain
    dataset by its path."""
    guide = (source / "docs/user-guide.md").read_text()
    layout = guide[guide.index("## Output (HDF5"):guide.index("### Output files")]
    for s in noether.output_series():
        parts = s["path"].split("/")
        if parts[1] == "checkpoint":
            assert s["path"] in layout, s["path"]
        elif parts[1] == "observables":
            observables = layout[layout.index("/observables/<name>"):layout.index("/checkpoint/")]
            assert parts[2] in observables, s["path"]
        else:
            assert "/".join(parts[:-1]) + "/{" in layout, s["path"]


def test_the_file_holds_each_shape_in_its_body_frame(source, tmp_path):
    """A polyhedron's mesh and an ellipsoid's semi-axes are in the output, so the file alone can
    draw the bodies: the mesh read back has the volume the run used (divergence theorem over its
    faces) and its centre of mass at the origin of the body frame."""
    out = tmp_path / "didymos.h5"
    sim = noether.Simulation(source / "examples/didymos.yaml", output=out, set=["run.t_end=60"])
    sim.integrate(60)
    sim.finish()
    shapes = noether.read(out).shapes
    assert shapes["dimorphos"]["kind"] == "ellipsoid"
    assert sorted(shapes["dimorphos"]["semi_axes"]) == sorted([103.16, 79.35, 66.13])
    mesh = shapes["didymos"]
    assert mesh["kind"] == "polyhedron" and mesh["vertices"].shape == (1000, 3) and mesh["faces"].shape == (1996, 3)
    v = mesh["vertices"][mesh["faces"]]  # [face][corner][xyz]
    signed = np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])) / 6  # tetrahedra from the origin
    with h5py.File(out, "r") as f:
        volume = f["parameters/shapes/didymos"].attrs["volume"][0]
    assert abs(signed.sum() / volume - 1) < 1e-12
    centroid = (signed[:, None] * v.sum(axis=1) / 4).sum(axis=0) / signed.sum()
    assert np.abs(centroid).max() < 1e-9 * np.abs(mesh["vertices"]).max()


def test_the_mutual_period_is_the_trajectorys(source, tmp_path):
    """Didymos for a day: the summary's mutual orbit period (whole revolutions of the relative
    position, crossings interpolated between frames) agrees within 1e-4 with a least-squares
    fit of the relative position's angle over the same revolutions; and it is not the osculating
    period of t0 (the ensemble's 12.054 h): the primary's oblateness speeds the orbit up."""
    out = tmp_path / "didymos.h5"
    sim = noether.Simulation(source / "examples/didymos.yaml", output=out, set=["run.t_end=86400"])
    sim.integrate(86400)
    summary = sim.finish()
    assert summary["mutual_pair"] == "didymos–dimorphos" and summary["mutual_revolutions"] == 2
    period = summary["mutual_period"]
    run = noether.read(out)
    t, x = run["time"], run["positions"]
    r = x[:, 1] - x[:, 0]
    angle = np.unwrap(np.arctan2(r[:, 1], r[:, 0]))
    within = t <= 2 * period
    slope = np.polyfit(t[within], angle[within], 1)[0]
    assert abs(2 * np.pi / slope / period - 1) < 1e-4, (2 * np.pi / slope, period)
    assert abs(period / 3600 - 11.933) < 2e-3, period / 3600


def test_the_binarys_series(source, tmp_path):
    """The binary's series, each against a second formulation: a Kepler orbit's osculating
    elements stay those the scene gave; the velocity in the primary's rotating frame is the rate
    of the position in that frame (central differences); Dimorphos, nearly synchronous, librates
    about its long axis pointing at Didymos instead of turning through 360 degrees."""
    kepler = {"G": 1, "bodies": [
        {"name": "sun", "mass": 1, "position": [0, 0, 0]},
        {"name": "planet", "mass": 1e-3, "orbit": {"around": "sun", "a": 1, "e": 0.5, "i": 30, "Omega": 40,
                                                    "omega": 50, "nu": 60}}],
        "potential": {"plugin": "point-mass"}, "integrator": {"plugin": "rk", "method": "rk4", "step": 1e-3},
        "run": {"t_end": 10, "output_every": 0.1}}
    sim = noether.Simulation(kepler, output=tmp_path / "kepler.h5")
    sim.integrate(10)
    sim.finish()
    run = noether.read(tmp_path / "kepler.h5")
    elements = run["osculating_elements"]
    assert np.abs(elements[:, :5] - [1, 0.5, 30, 40, 50]).max() < 1e-7, elements[-1]
    assert abs(elements[0, 5] - 60) < 1e-9 and run.unit("separation") == "L"
    assert np.allclose(run["separation"], np.linalg.norm(run["relative_positions"], axis=1), rtol=1e-15, atol=0)

    out = tmp_path / "didymos.h5"
    sim = noether.Simulation(source / "examples/didymos.yaml", output=out,
                             set=["run.t_end=43200", "run.output_every=30"])
    sim.integrate(43200)
    sim.finish()
    run = noether.read(out)
    r, v, t = run["relative_positions_primary_frame"], run["relative_velocities_primary_frame"], run["time"]
    rate = (r[2:] - r[:-2]) / (t[2:] - t[:-2])[:, None]
    assert np.abs(rate - v[1:-1]).max() < 1e-4 * np.abs(v).max(), np.abs(rate - v[1:-1]).max()
    libration = run["libration_angles"]
    assert run.unit("libration_angles") == "deg" and np.abs(libration).max() < 20, np.abs(libration).max()
    with h5py.File(out, "r") as f:
        assert f["observables/libration_angle"].attrs["secondary"] == "dimorphos"


def test_angular_velocity_is_the_attitudes_rate(source, tmp_path):
    """The output quantity added through the schema table alone (one row and its function):
    Ω = J⁻¹Π, checked against the attitudes' own rate, Ω̂ ≈ Rᵀ (R(t+h) − R(t−h)) / 2h."""
    out = tmp_path / "dumbbells.h5"
    sim = noether.Simulation(source / "examples/dumbbells.yaml", output=out,
                             set=["run.t_end=0.02", "run.output_every=1e-4", "integrator.step=1e-5"])
    sim.integrate(sim.run["t_end"])
    sim.finish()
    run = noether.read(out)
    omega, R, t = run["angular_velocities"], run["attitudes"], run["time"]
    assert run.unit("angular_velocities") == "rad/" + run.unit("time")
    h = t[1] - t[0]
    for k in range(1, len(t) - 1, 37):
        for b in range(R.shape[1]):
            W = R[k, b].T @ (R[k + 1, b] - R[k - 1, b]) / (2 * h)
            rate = np.array([W[2, 1], W[0, 2], W[1, 0]])
            assert np.abs(rate - omega[k, b]).max() <= 1e-5 * max(1.0, np.abs(omega[k, b]).max())


def test_compare_returns_a_table(source):
    table = noether.compare(source / "examples/dumbbells.yaml", set=["run.t_end=2"],
                            runs=[{"plugin": "lgvi", "step": [0.002, 0.001]}, "{plugin: rk, method: rk4, step: 0.001}"])
    assert len(table) == 3
    assert table["label"] == ["step=0.002", "step=0.001", "step=0.001"]
    err = table["final_position_error"]
    assert (table["ok"]).all() and (err > 0).all()
    assert 3.0 < err[0] / err[1] < 5.0  # the LGVI is of order 2: halving h divides the error by ~4
    assert "lgvi" in str(table) and table.reference


CHILD = textwrap.dedent("""
    import sys, noether
    scene, out, resume = sys.argv[1], sys.argv[2], sys.argv[3] == "1"
    sim = noether.Simulation.resume(out) if resume else noether.Simulation(scene, output=out, set=sys.argv[4:])
    sim.integrate(sim.run["t_end"])
    sim.finish()
""")


@pytest.mark.parametrize("integrator", ["{plugin: lgvi, step: 0.0002}", "{plugin: rk, method: rk4, step: 0.0002}"])
def test_runs_killed_in_python_and_resumed_are_bitwise_uninterrupted_runs(source, tmp_path, integrator):
    scene = str(source / "examples/dumbbells.yaml")
    sets = ["run.t_end=200", "run.output_every=0.01", "integrator=" + integrator]
    full, part = tmp_path / "full.h5", tmp_path / "part.h5"
    child = tmp_path / "child.py"
    child.write_text(CHILD)
    t = time.monotonic()
    subprocess.run([sys.executable, child, scene, full, "0"] + sets, check=True)
    duration = time.monotonic() - t
    rng = random.Random(7)
    kills, resume = 0, False
    while kills < 5:
        p = subprocess.Popen([sys.executable, child, scene, part, "1" if resume else "0"] + sets,
                             stderr=subprocess.PIPE, text=True)
        while not resume and not part.exists() and p.poll() is None:
            time.sleep(0.001)
        time.sleep(rng.uniform(0.02, 0.12) * duration)
        if p.poll() is None:
            p.send_signal(signal.SIGKILL)
            kills += 1
        err = p.communicate()[1]
        assert p.returncode in (0, -signal.SIGKILL) or "no complete frame" in err, err
        assert p.returncode != 0, "a run finished before its kill: the test needs a longer run"
        resume = "no complete frame" not in err
        if not resume:  # killed before its first block: start it again, as the message says
            part.unlink()
    # The last kill may have come before the first block was written, as in the loop: then the
    # run starts again (seen under load, beside the rest of the test suite). So may the last
    # kill of a resumed child that had already found no complete frame (the part then removed
    # above, seen once in CI).
    last = subprocess.run([sys.executable, child, scene, part, "1"], stderr=subprocess.PIPE, text=True) if resume else None
    if last is None or (last.returncode != 0 and "no complete frame" in last.stderr):
        part.unlink(missing_ok=True)
        last = subprocess.run([sys.executable, child, scene, part, "0"] + sets, stderr=subprocess.PIPE, text=True)
    assert last.returncode == 0, last.stderr
    with h5py.File(full, "r") as a, h5py.File(part, "r") as b:
        assert int(b["frames_complete"][()]) == len(a["particles/bodies/position/time"])
        assert (np.diff(b["particles/bodies/position/time"][()]) > 0).all()  # every frame once
        for key in ["particles/bodies/position/value", "checkpoint/linear_momentum", "checkpoint/attitude",
                    "particles/bodies/angular_momentum/value", "observables/energy/value",
                    "particles/bodies/position/step"]:
            assert a[key][()].tobytes() == b[key][()].tobytes(), key
        assert b["work"].attrs["outcome"] == "completed"


def test_another_interpreter_is_told_which_one(tmp_path):
    # The package without its compiled module: what a Python it was not built for (pyenv, a venv
    # of another version) meets on `import noether`.
    import shutil
    package = os.path.dirname(noether.__file__)
    shutil.copytree(package, tmp_path / "noether", ignore=shutil.ignore_patterns("_noether*", "__pycache__"))
    p = subprocess.run([sys.executable, "-c", "import noether"], cwd=tmp_path, capture_output=True, text=True,
                       env=dict(os.environ, PYTHONPATH=str(tmp_path)))
    assert p.returncode == 1
    assert "ImportError: noether's compiled module does not load in" in p.stderr, p.stderr
    assert "it is built for Debian's /usr/bin/python3" in p.stderr, p.stderr


def test_reading_without_h5py_says_what_is_missing(tmp_path):
    code = "import sys; sys.modules['h5py'] = None; import noether; noether.read(sys.argv[1])"
    p = subprocess.run([sys.executable, "-c", code, str(tmp_path / "run.h5")], capture_output=True, text=True)
    assert p.returncode == 1
    assert "noether.OutputError" in p.stderr or "OutputError" in p.stderr, p.stderr
    assert "needs h5py, which" in p.stderr and "python3-h5py" in p.stderr, p.stderr


def test_a_body_that_does_not_rotate_has_no_nutation_angle(source, tmp_path):
    """Eq. 17.11 measures Π from the axis of largest moment: without Π there is nothing to
    measure. The file says NaN (its description says why), the summary 'not rotating'; a body
    that rotates gets an angle in [0, 90]."""
    out = tmp_path / "alone.h5"
    sim = noether.Simulation(source / "examples/dumbbells.yaml", output=out,
                             set=["bodies.beta=~", "run.t_end=1", "bodies.alpha.angular_velocity=[0, 0, 0]"])
    sim.integrate(sim.run["t_end"])
    summary = sim.finish()
    assert "spin state alpha              not rotating" in sim.summary_text()
    nutation = summary["spin_states"][0]["max_nutation"]
    assert nutation is None or np.isnan(nutation)
    run = noether.read(out)
    assert np.isnan(run["nutation_angles"]).all()
    described = {s["name"]: s for s in noether.output_series()}["nutation_angles"]["description"]
    assert "NaN while the body does not rotate" in described
    sim = noether.Simulation(source / "examples/dumbbells.yaml", output=tmp_path / "spinning.h5",
                             set=["bodies.beta=~", "run.t_end=1"])
    sim.integrate(sim.run["t_end"])
    sim.finish()
    angles = noether.read(tmp_path / "spinning.h5")["nutation_angles"]
    assert ((angles >= 0) & (angles <= 90)).all()
