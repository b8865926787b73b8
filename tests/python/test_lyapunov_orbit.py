"""noether.lyapunov_orbit: a libration as a periodic orbit (docs/equations.md (19.3)), its period
against the pendulum's, its multipliers, and the scene it returns."""
import math

import numpy as np
import pytest

import noether


def rotation(axis, angle):
    k = np.asarray(axis) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


@pytest.fixture
def moon(source):
    return source / "examples" / "equilibria" / "synchronous-moon.yaml"


def test_on_the_flow_the_period_grows_as_the_pendulums(moon):
    theta0 = math.radians(3)
    orbit = noether.lyapunov_orbit(moon, "moon", 3, set=["integrator={plugin: rk, method: rkf78, rtol: 1e-13, atol: 1e-16}"])
    assert orbit["converged"] and orbit["steps"] == 0
    growth = orbit["period"] / orbit["linear_period"] - 1
    pendulum = theta0**2 / 4 + 11 * theta0**4 / 192
    assert growth == pytest.approx(pendulum, rel=0.02)  # m/M = 1e-3: measured +0.1 %
    # The monodromy from rkf78's variational equations (eq. 19.4): on the unit circle to 2.2e-8,
    # so the verdict is decided at the default tolerance 1e-6.
    assert orbit["monodromy"] == "tangent map"
    assert np.abs(np.abs(orbit["multipliers"]) - 1).max() < 1e-7 and orbit["verdict"] == "linearly stable"


def test_on_the_lgvi_the_orbit_is_the_maps_and_stable(moon):
    orbit = noether.lyapunov_orbit(moon, "moon", 3)
    assert orbit["converged"] and orbit["closure"] < 1e-12
    assert orbit["step"] * orbit["steps"] == pytest.approx(orbit["period"], rel=1e-15)
    assert len(orbit["family"]) == 2 and np.abs(orbit["family"] - 1).max() < 1e-4
    assert orbit["monodromy"] == "tangent map"  # the LGVI's discrete tangent map
    assert np.abs(np.abs(orbit["multipliers"]) - 1).max() < 1e-6 and orbit["verdict"] == "linearly stable"
    sim = noether.Simulation.from_yaml(orbit["scene"])
    d0 = sim.positions[1] - sim.positions[0]
    sim.integrate(orbit["period"])
    d1 = sim.positions[1] - sim.positions[0]
    back = rotation([0, 0, 1], -orbit["angle"])  # the scene's angular momentum is along +z
    assert np.linalg.norm(back @ d1 - d0) < 1e-10 * np.linalg.norm(d0)


def test_bad_requests(moon):
    with pytest.raises(noether.SceneError, match="point mass"):
        noether.lyapunov_orbit(moon, "primary", 3)
    with pytest.raises(noether.SceneError, match="between 0 and 45"):
        noether.lyapunov_orbit(moon, "moon", 60)
    with pytest.raises(noether.SceneError, match="no body 'deimos'"):
        noether.lyapunov_orbit(moon, "deimos", 3)
