"""noether.relative_equilibrium: the same equilibrium, modes and verdicts as `noether orbit
equilibrium` (docs/relative-equilibria.md), and a scene that runs from it."""
import math

import numpy as np
import pytest

import noether


def synchronous_moon(mass=1e-3, r=8.0):
    """A triaxial moon (0.2, 0.18, 0.15) locked to a unit point mass, as a dict scene."""
    return {
        "G": 1, "barycentric": True,
        "bodies": [
            {"name": "primary", "mass": 1, "position": [0, 0, 0]},
            {"name": "moon", "mass": mass, "shape": {"ellipsoid": {"semi_axes": [0.2, 0.18, 0.15]}},
             "orbit": {"around": "primary", "a": r, "nu": 0}, "attitude": {"quaternion": [0, 0, 0, 1]},
             "angular_velocity": [0, 0, math.sqrt((1 + mass) / r**3)]},
        ],
        "potential": {"plugin": "mutual-series", "order": 4},
        "integrator": {"plugin": "lgvi", "step": 0.1},
        "run": {"t_end": 100, "output_every": 1},
    }


def test_libration_matches_the_spin_orbit_formula_to_the_neglected_order():
    mass, r = 1e-3, 8.0
    eq = noether.relative_equilibrium(synchronous_moon(mass, r))
    assert eq["converged"] and eq["verdict"] == "linearly stable"
    assert eq["energetic_verdict"] == "energetically stable"
    libration = [m for m in eq["modes"] if m["motion"] == "libration of moon"]
    assert len(libration) == 1 and libration[0]["in_plane"]
    a, b, c = 0.2, 0.18, 0.15
    A, B, C = b * b + c * c, a * a + c * c, a * a + b * b  # × m/5, which cancels
    n = math.sqrt((1 + mass) / r**3)
    formula = n * math.sqrt(3 * (B - A) / C)
    assert abs(libration[0]["frequency"] / formula - 1) < 2 * (mass + (a / r) ** 2)
    assert eq["period"] == pytest.approx(2 * math.pi / eq["rate"])
    # every eigenvalue on the imaginary axis, in ± pairs
    lam = eq["eigenvalues"]
    assert np.abs(lam.real).max() < 1e-12 * np.abs(lam).max()
    assert np.allclose(np.sort(lam.imag), -np.sort(lam.imag)[::-1])


def test_the_scene_it_returns_runs_locked():
    eq = noether.relative_equilibrium(synchronous_moon())
    sim = noether.Simulation.from_yaml(eq["scene"])
    assert np.allclose(sim.positions, eq["positions"], rtol=0, atol=1e-15)
    sim.integrate(eq["period"])
    d = sim.positions[1] - sim.positions[0]
    assert np.linalg.norm(d) == pytest.approx(eq["separation"], rel=1e-7)  # a circle
    # the moon's long axis still on the line of centres, to the LGVI's phase error
    axis = sim.attitudes[0][:, 0]
    assert abs(abs(axis @ d) / np.linalg.norm(d) - 1) < 1e-6


def test_kw4_locked_is_darwin_unstable(source):
    eq = noether.relative_equilibrium(source / "examples" / "kw4-ellipsoids.yaml")
    assert eq["converged"] and eq["verdict"] == "unstable" and eq["in_plane_verdict"] == "unstable"
    growth = max(m["growth"] for m in eq["modes"])
    assert growth == pytest.approx(6.48e-6, rel=1e-2)  # docs/relative-equilibria.md: e-folding 1.8 days
    assert eq["energetic_index"] == 1


def test_bad_requests_are_scene_errors(source):
    with pytest.raises(noether.SceneError, match="'separation', 'angular-momentum' or 'rate'"):
        noether.relative_equilibrium(synchronous_moon(), fix="distance")
    with pytest.raises(noether.SceneError, match="no body 'deimos'"):
        noether.relative_equilibrium(synchronous_moon(), pair=["primary", "deimos"])
    with pytest.raises(noether.SceneError):  # an external field has no relative equilibria
        noether.relative_equilibrium(source / "examples" / "orbits" / "kepler-central.yaml")
    with pytest.raises(TypeError):
        noether.relative_equilibrium(42)
