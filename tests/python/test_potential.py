"""A potential written in Python (docs/python.md, "A potential in Python")."""
import numpy as np
import pytest

import noether


def point_masses(G, m):
    """U = −Σ G m_i m_j / r_ij and f_i = −∂U/∂x_i, for the Python potential's interface."""
    m = np.asarray(m, dtype=float)

    def potential(x, R):
        d = x[:, None, :] - x[None, :, :]  # x_i − x_j
        r = np.linalg.norm(d, axis=2)
        np.fill_diagonal(r, np.inf)
        mm = G * m[:, None] * m[None, :]
        U = -0.5 * np.sum(mm / r)
        f = -np.sum((mm / r**3)[:, :, None] * d, axis=1)
        return U, f, None

    return potential


def test_a_python_point_mass_potential_gives_the_plugins_trajectory(source):
    scene = source / "examples/figure-eight.yaml"
    plugin = noether.Simulation(scene)
    python = noether.Simulation(scene, potential=point_masses(1.0, [1, 1, 1]))
    h = 0.00632591398  # the scene's step: integrate(t) lands on the step grid t0 + k h
    with pytest.raises(noether.SceneError, match=r"integrate\(t\): t − t0 = 1 is not a whole number of steps"):
        plugin.integrate(1.0)
    for t in [158 * h, 6.32591398]:  # one period, in two calls
        plugin.integrate(t)
        python.integrate(t)
        # The same equations summed in another order: agreement to rounding, grown over the run.
        np.testing.assert_allclose(python.positions, plugin.positions, rtol=0, atol=1e-12)
        np.testing.assert_allclose(python.velocities, plugin.velocities, rtol=0, atol=1e-12)
    a, b = python.summary(), plugin.summary()
    assert a["potential"] == "python"
    assert a["E0"] == pytest.approx(b["E0"], rel=1e-14)
    assert a["max_abs_energy_error"] == pytest.approx(b["max_abs_energy_error"], rel=1e-6)


def test_python_potential_errors_are_clear(source, dumbbells):
    with pytest.raises(noether.SceneError, match="returned no moments, but the scene has rigid bodies"):
        noether.Simulation(dumbbells, potential=lambda x, R: (0.0, np.zeros((2, 3)), None))
    with pytest.raises(noether.SceneError, match=r"returned forces that is not a \(3, 3\) array"):
        noether.Simulation(source / "examples/figure-eight.yaml", potential=lambda x, R: (0.0, np.zeros(3), None))
    with pytest.raises(noether.SceneError, match="must return a tuple"):
        noether.Simulation(source / "examples/figure-eight.yaml", potential=lambda x, R: 1.0)
    with pytest.raises(noether.SceneError, match="expected a callable"):
        noether.Simulation(source / "examples/figure-eight.yaml", potential=3)

    calls = []

    def failing(x, R):
        calls.append(1)
        if len(calls) > 5:
            raise ValueError("bodies too close for this model")
        return point_masses(1.0, [1, 1, 1])(x, R)

    sim = noether.Simulation(source / "examples/figure-eight.yaml", potential=failing)
    with pytest.raises(noether.IntegrationError, match="the Python potential raised: ValueError: bodies too close"):
        sim.integrate(6.32591398)
    assert sim.t < 1.0


def test_a_checkpoint_of_a_python_potential_needs_it_again(source, tmp_path):
    scene = source / "examples/figure-eight.yaml"
    h = 0.00632591398
    f = point_masses(1.0, [1, 1, 1])
    sim = noether.Simulation(scene, potential=f)
    sim.integrate(100 * h)
    sim.save(tmp_path / "python.h5")
    with pytest.raises(noether.Error, match="pass the same potential to load it"):
        noether.Simulation.load(tmp_path / "python.h5")  # never silently the scene's plugin instead
    run = noether.Simulation(scene, potential=f, output=tmp_path / "run.h5")
    run.integrate(10 * h)
    del run  # closed before t_end
    with pytest.raises(noether.Error, match="potential was given in code"):
        noether.Simulation.resume(tmp_path / "run.h5")  # the file alone cannot continue it
    loaded = noether.Simulation.load(tmp_path / "python.h5", potential=f)
    loaded.integrate(1000 * h)
    sim.integrate(1000 * h)
    assert loaded.positions.tobytes() == sim.positions.tobytes()
