"""noether.relative_periodic_orbit: a relative periodic orbit shot on a scene's own integrator and
its multipliers (docs/relative-equilibria.md), against the equilibrium's linearisation."""
import math

import numpy as np
import pytest

import noether


def rotation(axis, angle):
    k = np.asarray(axis) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


@pytest.fixture
def kw4_locked(source, tmp_path):
    eq = noether.relative_equilibrium(source / "examples" / "kw4-ellipsoids.yaml")
    path = tmp_path / "kw4-locked.yaml"
    path.write_text(eq["scene"])
    return eq, path


def test_kw4_locked_as_a_discrete_lgvi_orbit(kw4_locked, tmp_path):
    eq, path = kw4_locked
    step = eq["period"] / 100
    orbit = noether.relative_periodic_orbit(path, set=[f"integrator.step={step!r}"])
    assert orbit["converged"] and orbit["closure"] < 1e-12 and orbit["integrator"] == "lgvi"
    assert not orbit["energy_conserved"]  # a symplectic map conserves a modified energy
    mu = orbit["multipliers"]
    # the Darwin pair: μ and 1/μ, μ close to exp(λT) of the linearisation (100 steps per period)
    growth = max(m["growth"] for m in eq["modes"])
    assert abs(mu).max() == pytest.approx(math.exp(growth * eq["period"]), rel=2e-3)
    assert abs(mu).max() * abs(mu).min() == pytest.approx(1, abs=1e-6)
    assert orbit["verdict"] == "unstable"
    # the scene it returns: the LGVI returns it turned by α about the axis
    sim = noether.Simulation.from_yaml(orbit["scene"])
    x0 = sim.positions - sim.positions.mean(axis=0)  # equal-mass weighting is enough for a turn
    sim.integrate(orbit["period"])
    x1 = sim.positions - sim.positions.mean(axis=0)
    back = rotation(orbit["axis"], -orbit["angle"])
    d0 = x0[1] - x0[0]
    assert np.linalg.norm(back @ (x1[1] - x1[0]) - d0) < 1e-9 * np.linalg.norm(d0)


def test_on_the_flow_every_multiplier_is_on_the_unit_circle(source, tmp_path):
    eq = noether.relative_equilibrium(source / "examples" / "equilibria" / "synchronous-moon.yaml")
    path = tmp_path / "moon.yaml"
    path.write_text(eq["scene"])
    orbit = noether.relative_periodic_orbit(path, set=["integrator={plugin: rk, method: rkf78, rtol: 1e-12}"])
    assert orbit["converged"] and orbit["energy_conserved"]
    assert orbit["verdict"] == "linearly stable"
    mu = orbit["multipliers"]
    assert np.abs(np.abs(mu) - 1).max() < 1e-6
    # each oscillation's multiplier is exp(i ν T): its angle is a frequency of the linearisation
    T = orbit["period"]
    for m in eq["modes"]:
        expected = np.exp(1j * m["frequency"] * T)
        assert np.abs(mu - expected).min() < 1e-6, m["motion"]


def test_no_orbit_near_a_scene_far_from_one(source):
    orbit = noether.relative_periodic_orbit(source / "examples" / "dumbbells.yaml", set=["run.t_end=0.5"])
    if orbit["converged"]:  # a dumbbell pair half an orbit on is not a relative periodic orbit
        pytest.fail(f"closed to {orbit['closure']}")
    assert "multipliers" not in orbit and "scene" not in orbit
    with pytest.raises(noether.SceneError, match="must be positive"):
        noether.relative_periodic_orbit(source / "examples" / "dumbbells.yaml", period=-1)
