"""noether.Simulation: the same numbers as the command, the state in and out, errors."""
import json
import subprocess

import h5py
import numpy as np
import pytest

import noether


def test_dumbbells_built_in_python_reproduce_the_command(dumbbells, source, noether_exe):
    # The scene as a dict, integrated in two calls; the command runs the YAML file in one go.
    sim = noether.Simulation(dumbbells)
    sim.integrate(7.3052)
    sim.integrate(20)
    got = sim.summary()
    cli = json.loads(subprocess.run([noether_exe, "run", str(source / "examples/dumbbells.yaml"), "--no-progress",
                                     "--summary", "json"], check=True, capture_output=True, text=True).stdout)
    assert f"{got['max_abs_energy_error']:.4e}" == "2.6962e-07"
    for key in ["E0", "max_abs_energy_error", "max_rel_angular_momentum_error", "max_orthogonality_error",
                "closest_approach", "t_of_closest_approach", "steps", "final_time"]:
        assert got[key] == cli[key], key
    # 7.3052 is not an output time: that call's end is one frame more than the command writes.
    assert got["output_frames"] == cli["output_frames"] + 1


def test_state_round_trip_is_exact(dumbbells):
    sim = noether.Simulation(dumbbells)
    sim.integrate(1.0)
    rng = np.random.default_rng(1)
    x = sim.positions + rng.normal(scale=1e-3, size=(2, 3))
    p = sim.momenta * 1.001
    R = sim.attitudes[::-1].copy()  # swap the two attitudes: rotations still
    Pi = sim.angular_momenta + 1e-3
    sim.set_state(positions=x, momenta=p, attitudes=R, angular_momenta=Pi)
    sim.integrate(sim.t)  # integrating to the current time changes nothing
    for got, want in [(sim.positions, x), (sim.momenta, p), (sim.attitudes, R), (sim.angular_momenta, Pi)]:
        assert got.tobytes() == want.tobytes()
    # Derived parts round-trip to rounding: v = γ/m, Ω = J⁻¹Π, quaternions.
    v, w, q = sim.velocities, sim.angular_velocities, sim.quaternions
    sim.velocities, sim.angular_velocities, sim.quaternions = v, w, q
    np.testing.assert_allclose(sim.velocities, v, rtol=1e-15)
    np.testing.assert_allclose(sim.angular_velocities, w, rtol=1e-14)
    np.testing.assert_allclose(sim.attitudes, R, atol=1e-15)


def test_a_state_set_between_calls_is_where_the_run_continues(dumbbells):
    # Stop at t = 2, reset to the state of t = 1, integrate one unit: the state of t = 2 again,
    # bitwise (the LGVI step map is a function of the state alone).
    sim = noether.Simulation(dumbbells)
    sim.integrate(1.0)
    x1, p1, R1, Pi1 = sim.positions, sim.momenta, sim.attitudes, sim.angular_momenta
    sim.integrate(2.0)
    x2 = sim.positions
    sim.set_state(t=1.0, positions=x1, momenta=p1, attitudes=R1, angular_momenta=Pi1)
    sim.integrate(2.0)
    assert sim.positions.tobytes() == x2.tobytes()


def test_attitudes_that_are_not_rotations_raise(dumbbells):
    sim = noether.Simulation(dumbbells)
    before = sim.attitudes
    with pytest.raises(noether.Error, match=r"attitude of 'beta' is not a rotation \(\|\|I - R\^T R\|\| = "):
        sim.attitudes = np.stack([np.eye(3), 2 * np.eye(3)])
    with pytest.raises(noether.Error, match=r"det R = -1"):
        sim.attitudes = np.stack([np.eye(3), -np.eye(3)])  # orthogonal, a reflection
    with pytest.raises(noether.Error, match=r"expected an array of shape \(2, 3, 3\)"):
        sim.attitudes = np.eye(3)
    with pytest.raises(noether.Error, match="not a unit quaternion"):
        sim.quaternions = [[1, 0, 0, 0], [1, 1, 0, 0]]
    with pytest.raises(noether.Error, match="unknown part 'spin'"):
        sim.set_state(spin=[0, 0, 1])
    assert sim.attitudes.tobytes() == before.tobytes()  # nothing changed


def test_set_state_refuses_what_the_scene_refuses(dumbbells, source):
    # The command refuses a scene whose bodies start at one position, or inside each other when
    # the run stops at collisions; set_state refuses the same states (issue 63, item 6), and
    # changes nothing.
    sim = noether.Simulation(dumbbells)
    before = sim.positions
    with pytest.raises(noether.Error, match="bodies 'alpha' and 'beta' start at the same position"):
        sim.positions = np.zeros((2, 3))
    assert sim.positions.tobytes() == before.tobytes()
    fall = noether.Simulation(source / "examples/collision.yaml")  # spheres of radius 0.05
    with pytest.raises(noether.Error, match=r"bodies 'left' and 'right' overlap at the start: 0\.02 inside"):
        fall.positions = [[-0.04, 0, 0], [0.04, 0, 0]]
    fall.positions = [[-0.06, 0, 0], [0.06, 0, 0]]  # apart: taken
    assert fall.integrate(2.0)["event"] == "collision"


def test_wrong_argument_types_are_argument_errors(dumbbells, tmp_path):
    # What is not a number, an array of real numbers or a path raises noether.ArgumentError — a
    # noether.Error and a TypeError — named after the call, and changes nothing; complex values
    # are refused, not cast to real with their imaginary parts dropped (issue 63, item 6).
    sim = noether.Simulation(dumbbells)
    before = sim.positions
    probes = [
        (lambda: sim.set_state(positions=before * (1 + 1e-3j)), r"Simulation\.set_state: positions: complex values"),
        (lambda: setattr(sim, "t", 1 + 2j), r"Simulation\.set_state: t: \(1\+2j\) is complex"),
        (lambda: setattr(sim, "t", "abc"), r"t: expected a real number, not str 'abc'"),
        (lambda: setattr(sim, "momenta", [["a", "b", "c"], [1, 2, 3]]), r"momenta: expected an array of real numbers"),
        (lambda: sim.integrate("10"), r"Simulation\.integrate: t: expected a real number, not str"),
        (lambda: sim.integrate(None), r"Simulation\.integrate: t: expected a real number, not NoneType"),
        (lambda: sim.sensitivity(3), r"Simulation\.sensitivity: name: a key of sensitivity_names"),
        (lambda: sim.save(3), r"Simulation\.save: path: expected a path"),
        (lambda: noether.Simulation.load(None), r"Simulation\.load: path: expected a path"),
        (lambda: noether.Simulation(42), r"^Simulation: scene: a path to a YAML scene"),
        (lambda: noether.relative_equilibrium(42), r"^relative_equilibrium: scene: a path"),
        (lambda: noether.stokes(tmp_path / "x.yaml", "a", degree="eight"), r"^stokes: "),
    ]
    for call, message in probes:
        with pytest.raises(noether.ArgumentError, match=message) as raised:
            call()
        assert isinstance(raised.value, noether.Error) and isinstance(raised.value, TypeError)
    assert sim.positions.tobytes() == before.tobytes() and sim.t == 0.0
    sim.set_state(positions=before.astype(np.float32).astype(np.int64) + before)  # integers are numbers
    sim.set_state(t=np.float32(0.5))


def test_input_that_looks_like_a_unit_slip_is_warned(source):
    # A density typed in g/cm³ where kg/m³ goes (issue 63, item 4): an InputWarning at the user's
    # line with the numbers, and the same text in the summary's warnings; the run is unchanged.
    with pytest.warns(noether.InputWarning, match=r"its density 2\.2 kg/m³ is outside the 50–25000 kg/m³.*"
                      r"was it in g/cm³ \(2\.2e\+03 kg/m³\)\?") as caught:
        sim = noether.Simulation(source / "examples/didymos.yaml",
                                 set=["bodies.dimorphos.density=2.2", "run.t_end=60", "run.output_every=60"])
    assert caught[0].filename == __file__
    warnings = sim.summary()["warnings"]
    assert len(warnings) == 1 and warnings[0] == str(caught[0].message)
    sim.integrate(60)
    assert sim.finish()["warnings"] == warnings


def test_scene_errors_carry_file_and_line(tmp_path, source):
    bad = tmp_path / "bad.yaml"
    bad.write_text((source / "examples/dumbbells.yaml").read_text().replace("mass: 3", "mass: -3"))
    with pytest.raises(noether.SceneError, match=r"bad\.yaml:\d+"):
        noether.Simulation(bad)
    with pytest.raises(noether.SceneError, match="integrator.step"):
        noether.Simulation(source / "examples/dumbbells.yaml", set=["integrator.step=abc"])
    with pytest.raises(noether.PluginError, match="no-such-plugin"):
        noether.Simulation(source / "examples/dumbbells.yaml", set=["integrator={plugin: no-such-plugin}"])
    with pytest.raises(noether.ArgumentError):
        noether.Simulation(42)


def test_integration_errors_are_exceptions_and_keep_the_last_valid_state(source):
    sim = noether.Simulation(source / "examples/dumbbells.yaml", set=["integrator={plugin: cvode, max_steps: 50}",
                                                                      "run.output_every=5"])
    with pytest.raises(noether.IntegrationError, match="max_steps"):
        sim.integrate(20)
    assert 0 < sim.t < 20
    assert np.isfinite(sim.positions).all()


def test_save_and_load_continue_bit_for_bit(dumbbells, tmp_path):
    for integrator in [{"plugin": "lgvi", "step": 0.0002}, {"plugin": "rk", "method": "rk4", "step": 0.0002}]:
        dumbbells["integrator"] = integrator
        whole = noether.Simulation(dumbbells)
        whole.integrate(3.0)
        part = noether.Simulation(dumbbells)
        part.integrate(1.3702)  # between output times: one frame more
        part.save(tmp_path / "sim.h5")
        del part
        loaded = noether.Simulation.load(tmp_path / "sim.h5")
        assert loaded.t == 1.3702
        loaded.integrate(3.0)
        for name in ["positions", "momenta", "attitudes", "angular_momenta"]:
            assert getattr(loaded, name).tobytes() == getattr(whole, name).tobytes(), (integrator, name)
        a, b = loaded.summary(), whole.summary()
        for key in ["E0", "max_abs_energy_error", "max_rel_angular_momentum_error", "steps", "output_frames"]:
            assert a[key] == b[key] + (1 if key == "output_frames" else 0), (integrator, key)


def test_one_checkpoint_format_output_files_load_and_saved_files_resume(dumbbells, tmp_path):
    """A saved simulation is an output file with one frame, and load() reads any output file:
    each continues bit for bit whichever way it is opened."""
    dumbbells["run"]["t_end"] = 1.0
    whole = noether.Simulation(dumbbells)
    whole.integrate(1.0)
    # An output file, loaded: continues from its last frame with the whole run's summary.
    run = noether.Simulation(dumbbells, output=tmp_path / "run.h5")
    run.integrate(0.5)
    run.finish()
    loaded = noether.Simulation.load(tmp_path / "run.h5")
    assert loaded.t == 0.5
    loaded.integrate(1.0)
    assert loaded.positions.tobytes() == whole.positions.tobytes()
    assert loaded.attitudes.tobytes() == whole.attitudes.tobytes()
    a, b = loaded.summary(), whole.summary()
    for key in ["E0", "max_abs_energy_error", "max_rel_angular_momentum_error", "steps", "output_frames"]:
        assert a[key] == b[key], key
    # A saved simulation: an output file of one frame, read by noether.read and continued by resume.
    part = noether.Simulation(dumbbells)
    part.integrate(0.3702)
    part.save(tmp_path / "saved.h5")
    saved = noether.read(tmp_path / "saved.h5")
    assert saved.frames == 1 and saved.outcome.startswith("saved at t = 0.3702")
    assert saved["momenta"][0].tobytes() == part.momenta.tobytes()
    resumed = noether.Simulation.resume(tmp_path / "saved.h5")
    resumed.integrate(resumed.run["t_end"])
    assert resumed.positions.tobytes() == whole.positions.tobytes()
    assert resumed.angular_momenta.tobytes() == whole.angular_momenta.tobytes()
    resumed.finish()
    with pytest.raises(noether.OutputError, match="no such file"):
        noether.Simulation.load(tmp_path / "missing.h5")
    with h5py.File(tmp_path / "old.h5", "w") as f:  # Simulation.save's own layout before this version
        f.attrs["format"] = "noether simulation checkpoint 1"
    with pytest.raises(noether.OutputError, match="saved by an older noether"):
        noether.Simulation.load(tmp_path / "old.h5")


def test_numpy_values_in_a_scene_dict_are_their_numbers(dumbbells, tmp_path):
    """Arrays and NumPy scalars in a scene dict (what a script computes) are taken as the lists
    and numbers they hold: the same run, bit for bit; anything else is a SceneError naming it."""
    plain = noether.Simulation(dumbbells, set=["run.t_end=0.1"])
    plain.integrate(0.1)
    arrays = dict(dumbbells)
    arrays["bodies"] = [dict(b) for b in dumbbells["bodies"]]
    for b in arrays["bodies"]:
        b["position"] = np.array(b["position"], dtype=float)
        b["inertia"] = np.array(b["inertia"])
    arrays["bodies"][0]["mass"] = np.float64(1.5)
    arrays["G"] = np.float64(dumbbells["G"])
    arrays["run"] = dict(dumbbells["run"], output_every=np.float64(0.01))
    sim = noether.Simulation(arrays, set=["run.t_end=0.1"])
    sim.integrate(0.1)
    assert sim.positions.tobytes() == plain.positions.tobytes()
    arrays["bodies"][1]["mass"] = object()
    with pytest.raises(noether.SceneError, match="is not a number, string, list or dict"):
        noether.Simulation(arrays)


def test_reading_what_is_not_an_output_file_is_an_output_error(tmp_path):
    with pytest.raises(noether.OutputError, match="no such file"):
        noether.read(tmp_path / "missing.h5")
    (tmp_path / "text.h5").write_text("not HDF5")
    with pytest.raises(noether.OutputError, match="not an HDF5 file"):
        noether.read(tmp_path / "text.h5")
    with h5py.File(tmp_path / "other.h5", "w") as f:
        f["x"] = 1
    with pytest.raises(noether.OutputError, match="not an output file of noether"):
        noether.read(tmp_path / "other.h5")


def test_plugins_are_listed(noether_exe):
    # Every plugin the driver lists loads in Python too, without a warning: a plugin that relies on
    # a library the driver's process has loaded (spherical-harmonics and fmt did) fails only here.
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        names = {p["name"]: p for p in noether.plugins()}
    listed = subprocess.run([noether_exe, "plugins"], capture_output=True, text=True, check=True).stdout.split("\n")
    driver = {line.split()[1] for line in listed if line.split()[:1] in (["potential"], ["integrator"], ["force"])}
    assert driver and set(names) == driver, (sorted(names), sorted(driver))
    assert names["lgvi"]["kind"] == "integrator"
    assert any(q["name"] == "step" for q in names["lgvi"]["params"])


def test_damaged_checkpoints_are_refused_by_name_or_load_the_same(dumbbells, tmp_path):
    # docs/reliability.md, "Checksums": 150 seeded damages (1-8 flipped bits, or a 512-byte block
    # zeroed) of a saved simulation; load() either raises noether.Error naming the file, or gives
    # the undamaged checkpoint's state and summary exactly (the damage was in bytes it does not
    # read). Never a different state.
    dumbbells["integrator"] = {"plugin": "lgvi", "step": 0.0002, "frame": "relative", "form": "lagrangian"}
    sim = noether.Simulation(dumbbells)
    sim.integrate(0.5)
    path = tmp_path / "sim.h5"
    sim.save(path)
    reference = noether.Simulation.load(path)
    names = ["positions", "momenta", "attitudes", "angular_momenta"]
    expected = {n: getattr(reference, n).tobytes() for n in names}
    expected_summary = {k: v for k, v in reference.summary().items() if "wall" not in k}
    original = path.read_bytes()
    rng = np.random.default_rng(20261124)
    outcomes = {"refused": 0, "same": 0}
    for case in range(150):
        data = bytearray(original)
        if rng.random() < 0.5:
            for _ in range(rng.integers(1, 9)):
                data[rng.integers(len(data))] ^= 1 << int(rng.integers(8))
        else:
            start = int(rng.integers(len(data)))
            data[start:start + 512] = bytes(len(data[start:start + 512]))
        damaged = tmp_path / f"case-{case}.h5"
        damaged.write_bytes(bytes(data))
        try:
            loaded = noether.Simulation.load(damaged)
        except noether.Error as e:
            assert str(damaged) in str(e), (case, str(e))
            assert damaged.read_bytes() == bytes(data), case
            outcomes["refused"] += 1
            continue
        assert loaded.t == reference.t, case
        for n in names:
            assert getattr(loaded, n).tobytes() == expected[n], (case, n)
        got = {k: v for k, v in loaded.summary().items() if "wall" not in k}
        assert got == expected_summary, case
        outcomes["same"] += 1
    print("damaged checkpoints:", outcomes, "file", len(original), "bytes")
    assert outcomes["refused"] > 0 and outcomes["same"] > 0, outcomes


def test_ctrl_c_stops_integrate_between_steps(dumbbells):
    # SIGINT while C++ integrates: KeyboardInterrupt within a fraction of a second, the state
    # kept where the loop stopped (it used to be seen only when integrate returned: here, after
    # 10^9 steps, hours).
    import os
    import signal
    import threading
    import time
    sim = noether.Simulation(dumbbells)
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        sim.integrate(2e5)
    elapsed = time.monotonic() - start
    timer.join()
    assert elapsed < 3.0, elapsed
    assert 0 < sim.t < 2e5
    assert np.isfinite(sim.positions).all()
    sim.integrate(round(sim.t) + 1.0)  # and it goes on afterwards


def test_force_jacobian_is_minus_the_second_derivative_of_u(dumbbells, source):
    # K = ∂(f, M)/∂(x, θ) (docs/equations.md §20): on positions, −∂²U/∂x∂x, here against second
    # differences of the potential energy taken through set_state and diagnostics().
    sim = noether.Simulation(dumbbells)
    sim.integrate(1.0)
    K, analytic = sim.force_jacobian()
    assert analytic and K.shape == (12, 12)
    x0 = sim.positions
    h = 1e-4

    def U(dx):
        sim.positions = x0 + dx.reshape(2, 3)
        return sim.diagnostics()["potential_energy"]
    H = np.zeros((6, 6))
    for a in range(6):
        for b in range(6):
            ea, eb = np.eye(6)[a] * h, np.eye(6)[b] * h
            H[a, b] = (U(ea + eb) - U(ea - eb) - U(eb - ea) + U(-ea - eb)) / (4 * h * h)
    sim.positions = x0
    assert np.abs(K[:6, :6] + H).max() < 1e-5 * np.abs(H).max()
    # mutual-series' K is its own (docs/equations.md §25), and so is mutual-exact's (§26): on the
    # KW4 ellipsoids at order 4 the two agree to the series' truncation, attitudes too.
    kw4 = str(source / "examples/kw4-ellipsoids.yaml")
    K2, analytic2 = noether.Simulation(kw4).force_jacobian()
    K3, analytic3 = noether.Simulation(kw4, set=["potential={plugin: mutual-exact}"]).force_jacobian()
    assert analytic2 and analytic3 and K3.shape == (12, 12) and np.all(np.isfinite(K3))
    assert np.abs(K2 - K3).max() < 1e-2 * np.abs(K3).max()


def test_stm_is_the_derivative_of_the_run(dumbbells, tmp_path):
    # sim.stm (docs/derivatives.md) against central differences of whole runs, taken through
    # set_state on fresh simulations: the columns of alpha's position and of beta's angular
    # momentum, and the STM the output file holds at its last frame.
    dumbbells["run"].update(t_end=0.4, output_every=0.2)
    sim = noether.Simulation(dumbbells, stm=True, output=str(tmp_path / "stm.h5"))
    assert np.array_equal(sim.stm, np.eye(24))
    sim.integrate(0.2)
    sim.integrate(0.4)  # two calls: the STM goes on from where the first left it
    M = sim.stm
    names = sim.stm_coordinates
    assert M.shape == (24, 24) and names[0] == "alpha.position.x" and names[21] == "beta.angular_momentum.x"
    assert abs(np.linalg.det(M) - 1) < 1e-12

    def final(**moved):
        run = noether.Simulation(dumbbells)
        run.set_state(**moved)
        run.integrate(0.4)
        return np.concatenate([run.positions.ravel(), run.momenta.ravel(), run.angular_momenta.ravel()])

    start = noether.Simulation(dumbbells)
    x0, Pi0 = start.positions, start.angular_momenta
    rows = list(range(6)) + list(range(12, 24))  # positions, momenta and angular momenta
    for column, h, moved in ((0, 1e-6, lambda s: dict(positions=x0 + s * np.eye(6)[0].reshape(2, 3))),
                             (21, 1e-5, lambda s: dict(angular_momenta=Pi0 + s * np.eye(6)[3].reshape(2, 3)))):
        difference = (final(**moved(h)) - final(**moved(-h))) / (2 * h)
        assert np.abs(difference - M[rows, column]).max() < 1e-6 * np.abs(M[rows, column]).max(), column
    sim.finish()
    out = noether.read(tmp_path / "stm.h5")
    assert out["stm"].shape == (3, 24, 24)
    assert np.array_equal(out["stm"][0], np.eye(24)) and np.array_equal(out["stm"][-1], M)


def test_stm_restarts_at_a_new_state_and_is_absent_unless_asked(dumbbells):
    assert noether.Simulation(dumbbells).stm is None
    sim = noether.Simulation(dumbbells, stm=True)
    sim.integrate(0.1)
    assert not np.allclose(sim.stm, np.eye(24))
    sim.positions = sim.positions  # a new segment
    assert np.array_equal(sim.stm, np.eye(24))
    dumbbells["integrator"] = {"plugin": "cvode", "frame": "relative"}
    with pytest.raises(noether.SceneError, match="cannot carry the state-transition matrix"):
        noether.Simulation(dumbbells, stm=True)


def test_sensitivities_follow_the_stm_and_the_scene_keys(dumbbells, tmp_path):
    # sim.sensitivities (docs/derivatives.md): with the STM carried too, the sensitivity to
    # alpha's spin Ω_z is the STM times the initial column (∂Π/∂Ω_z = J e_z, the rest 0); the
    # file holds the same; set_state is refused; a mass is not an initial-state key.
    dumbbells["run"].update(t_end=0.2, output_every=0.1)
    sim = noether.Simulation(dumbbells, stm=True, sensitivities=["bodies.alpha.angular_velocity.2"],
                             output=str(tmp_path / "sens.h5"))
    assert sim.sensitivity_names == ["bodies.alpha.angular_velocity.2"]
    start = sim.sensitivities
    assert start.shape == (24, 1)
    J_zz = dumbbells["bodies"][0]["inertia"][2]
    e = np.zeros(24)
    e[20] = J_zz  # alpha.angular_momentum.z
    assert np.abs(start[:, 0] - e).max() < 1e-9 * J_zz
    sim.integrate(0.2)
    assert np.abs(sim.sensitivities - sim.stm @ start).max() < 1e-12 * np.abs(sim.stm).max() * J_zz
    with pytest.raises(noether.Error, match="carries sensitivities"):
        sim.positions = sim.positions
    sim.finish()
    out = noether.read(tmp_path / "sens.h5")
    assert out["sensitivity"].shape == (3, 24, 1)
    assert np.array_equal(sim.sensitivity("bodies.alpha.angular_velocity.2"), sim.sensitivities[:, 0])
    with pytest.raises(KeyError, match="carries no sensitivity to 'bodies.beta.mass'"):
        sim.sensitivity("bodies.beta.mass")


def test_sensitivity_to_a_mass_matches_runs_with_the_mass_moved():
    # sim.sensitivity("bodies.moon.mass") (docs/derivatives.md): a moon on an eccentric orbit
    # given by its elements — its start and every step depend on its mass — against central
    # differences of two whole runs with the mass moved by ±1e-6 of itself.
    def scene(mass):
        return {"G": 1, "barycentric": True,
                "bodies": [{"name": "planet", "mass": 1, "position": [0, 0, 0], "velocity": [0, 0, 0]},
                           {"name": "moon", "mass": mass, "orbit": {"around": "planet", "a": 1, "e": 0.4, "M": 10}}],
                "potential": {"plugin": "point-mass"}, "integrator": {"plugin": "lgvi", "step": 1e-3},
                "run": {"t_end": 2, "output_every": 1}}

    def final(mass):
        sim = noether.Simulation(scene(mass))
        sim.integrate(2)
        return np.concatenate([sim.positions.ravel(), sim.momenta.ravel()])

    sim = noether.Simulation(scene(0.01), sensitivities=["bodies.moon.mass"])
    sim.integrate(2)
    column = sim.sensitivity("bodies.moon.mass")
    h = 1e-8
    fd = (final(0.01 + h) - final(0.01 - h)) / (2 * h)
    assert np.linalg.norm(column - fd) < 1e-6 * np.linalg.norm(fd)


def _ellipsoid_lattice(k):
    """k tumbling ellipsoids on a cubic lattice (tests/test_support.hpp's ellipsoid_lattice_scene)."""
    side = 1
    while side ** 3 < k:
        side += 1
    bodies = []
    for n in range(k):
        i, j, l = n % side, (n // side) % side, n // (side * side)
        bodies.append({"name": f"e{n}", "mass": 1, "shape": {"ellipsoid": {"semi_axes": [1, 0.8, 0.6]}},
                       "position": [4.0 * i + 0.1 * np.sin(0.37 * n), 4.0 * j + 0.1 * np.cos(0.37 * n), 4.0 * l],
                       "velocity": [0.01 * np.cos(0.11 * n), 0.01 * np.sin(0.11 * n), 0],
                       "attitude": {"euler_angles": [17.0 * n, 5.0 * (n % 7), 3.0 * (n % 5)]},
                       "angular_velocity": [0.01, 0, 0.1 + 0.01 * n]})
    return {"G": 1, "bodies": bodies, "potential": {"plugin": "mutual-series", "order": 4},
            "integrator": {"plugin": "lgvi", "step": 0.01}, "run": {"t_end": 0.2, "output_every": 0.1}}


def test_threads_give_the_same_run_bit_for_bit(monkeypatch):
    # Simulation(threads=N) as `noether run --threads N` (docs/user-guide.md, "Threads"): 27 bodies'
    # 351 pairs on 1 and 2 threads, the same states bit for bit; the keyword wins over
    # NOETHER_THREADS, which applies without it.
    monkeypatch.setenv("NOETHER_THREADS", "2")
    runs = {}
    for threads in (1, None):
        sim = noether.Simulation(_ellipsoid_lattice(27), threads=threads)
        sim.integrate(0.2)
        runs[threads] = sim
    assert runs[1].summary()["threads"] == 1
    assert runs[None].summary()["threads"] == 2  # from the environment
    monkeypatch.delenv("NOETHER_THREADS")
    assert noether.Simulation(_ellipsoid_lattice(2), threads=3).summary()["threads"] == 3
    assert noether.Simulation(_ellipsoid_lattice(2)).summary()["threads"] == 1
    assert np.array_equal(runs[None].positions, runs[1].positions)
    assert np.array_equal(runs[None].attitudes, runs[1].attitudes)
    assert runs[None].summary()["max_abs_energy_error"] == runs[1].summary()["max_abs_energy_error"]
    assert np.abs(runs[1].positions - np.array([b["position"] for b in _ellipsoid_lattice(27)["bodies"]])).max() > 1e-4
    for bad in (0, -1, 1.5, True, "2"):
        with pytest.raises(noether.SceneError, match="threads must be a positive whole number"):
            noether.Simulation(_ellipsoid_lattice(2), threads=bad)


def test_dart_in_python_gives_the_period_change_the_command_prints(source, noether_exe, tmp_path):
    # ΔP in one run (docs/user-guide.md "Verdict"): Python's finish() carries the same period
    # changes, with their errors, as the command's JSON — the impulse applied in a call of its own.
    scene = str(source / "examples/didymos-dart.yaml")
    sim = noether.Simulation(scene)
    sim.integrate(86400)
    sim.integrate(259200)
    got = sim.finish()["period_changes"]
    cli = json.loads(subprocess.run([noether_exe, "run", scene, "--no-progress", "--summary", "json", "-o",
                                     str(tmp_path / "dart.h5")], check=True, capture_output=True, text=True).stdout)
    assert len(got) == 1 and got[0]["t"] == 86400
    assert -23.9 < got[0]["change"] / 60 < -23.8
    assert 0 < got[0]["change_error"] < got[0]["before_error"] / 30
    assert got[0]["error_method"] == "the run repeated at half the step, Richardson order 2"
    assert got == cli["period_changes"]
