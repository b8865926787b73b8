"""Property-based fuzzing of the Python API with Hypothesis (Debian's python3-hypothesis):
scenes as dicts, set_state, save/load (docs/reliability.md, "Fuzzing").

Properties:
- any dict scene either builds a Simulation or raises noether.SceneError / noether.PluginError
  (never another exception, never a crash); one that builds integrates or raises
  noether.IntegrationError, and a state it reaches is finite;
- any set_state either raises noether.Error (noether.ArgumentError for what is not an array of
  real numbers: text, None, complex values) and leaves the state as it was, or is read back bit
  for bit;
- save then load gives the same state bit for bit, and both continue identically.

The default run tries a few dozen examples per property (derandomised: the same examples every
run); the slow tier (`fuzz.python-api`) sets NOETHER_HYPOTHESIS_EXAMPLES for a larger round.
"""
import math
import os

import numpy as np
import pytest

from hypothesis import HealthCheck, event, given, settings  # tools/install-deps.sh: python3-hypothesis
from hypothesis import strategies as st

import noether

EXAMPLES = int(os.environ.get("NOETHER_HYPOTHESIS_EXAMPLES", "25"))
SETTINGS = settings(max_examples=EXAMPLES, derandomize=True, database=None, deadline=None,
                    suppress_health_check=list(HealthCheck))

finite = st.floats(min_value=-1e3, max_value=1e3, allow_nan=False, allow_infinity=False)
wild = st.one_of(finite, st.floats(), st.sampled_from([0.0, -0.0, 1e308, -1e308, 1e-308, 5e-324]))
number = st.one_of(finite, wild, st.integers(-10, 10), st.text(max_size=4), st.none(), st.booleans())


@st.composite
def scenes(draw):
    """A valid scene (1–4 bodies, point masses and ellipsoids, a potential and an integrator that
    fit them), then up to three mutations: a value replaced by a wild one or one of the wrong
    type, a key deleted, a key added."""
    n = draw(st.integers(1, 4))
    bodies = []
    for k in range(n):
        body = {"name": f"b{k}", "mass": draw(st.floats(0.1, 10)),
                "position": [3.0 * k, draw(st.floats(-1, 1)), 0.0],
                "velocity": [draw(st.floats(-0.5, 0.5)), draw(st.floats(-0.5, 0.5)), 0.0]}
        if draw(st.booleans()):
            body["shape"] = {"ellipsoid": {"semi_axes": [draw(st.floats(0.5, 1)), draw(st.floats(0.3, 0.5)), 0.3]}}
            body["angular_velocity"] = [0.0, 0.0, draw(st.floats(-2, 2))]
        bodies.append(body)
    potential = draw(st.sampled_from([{"plugin": "point-mass"}, {"plugin": "mutual-series", "order": 2},
                                      {"plugin": "mutual-series", "tolerance": 1e-8}]))
    integrator = draw(st.sampled_from([{"plugin": "lgvi", "step": 0.01},
                                       {"plugin": "rk", "method": "rk4", "step": 0.01},
                                       {"plugin": "rk", "method": "dopri5", "rtol": 1e-9, "atol": 1e-12},
                                       {"plugin": "cvode", "rtol": 1e-9, "atol": 1e-12}]))
    scene = {"G": 1.0, "bodies": bodies, "potential": potential, "integrator": dict(integrator),
             "run": {"t_end": 0.1, "output_every": 0.05}}
    for _ in range(draw(st.integers(0, 3))):
        # Every (container, key) of the scene, then one mutation there.
        places = []

        def walk(node):
            items = node.items() if isinstance(node, dict) else enumerate(node)
            for key, value in list(items):
                places.append((node, key))
                if isinstance(value, (dict, list)):
                    walk(value)
        walk(scene)
        node, key = draw(st.sampled_from(places))
        what = draw(st.sampled_from(["value", "value", "delete", "add"]))
        if what == "value":
            node[key] = draw(value_strategy)
        elif what == "delete" and isinstance(node, dict):
            del node[key]
        elif what == "delete":
            node.pop(key)
        elif isinstance(node, dict):
            node[draw(st.text(max_size=8))] = draw(value_strategy)
        else:
            node.append(draw(value_strategy))
    return scene


value_strategy = st.one_of(wild, wild, number, st.lists(number, max_size=4),
                           st.dictionaries(st.text(max_size=5), number, max_size=2))


@SETTINGS
@given(scenes())
def test_any_dict_scene_builds_or_is_refused_by_name(scene):
    try:
        sim = noether.Simulation(scene)
    except (noether.SceneError, noether.PluginError) as e:
        assert str(e), "an error without a message"
        event("refused")
        return
    try:
        result = sim.integrate(min(0.1, sim.run["t_end"]) if "t_end" in sim.run else 0.1)
    except noether.IntegrationError as e:
        assert str(e)
        assert np.all(np.isfinite(sim.positions)), "the kept state is not finite"
        event("integration failed")
        return
    except noether.SceneError as e:  # a time off a fixed-step grid
        assert "step" in str(e), str(e)
        event("time off the step grid")
        return
    event("integrated")
    assert isinstance(result, dict)
    for part in (sim.positions, sim.momenta, sim.attitudes, sim.angular_momenta):
        assert np.all(np.isfinite(part)), "a state that is not finite after a successful integrate"


def dumbbells_sim(dumbbells):
    sim = noether.Simulation(dumbbells)
    sim.integrate(0.01)
    return sim


def state(sim):
    return [sim.t, sim.positions.tobytes(), sim.momenta.tobytes(), sim.attitudes.tobytes(),
            sim.angular_momenta.tobytes()]


def rotations(n):
    quaternions = st.lists(st.lists(st.floats(-1, 1), min_size=4, max_size=4), min_size=n, max_size=n)
    return quaternions.filter(lambda qs: all(np.linalg.norm(q) > 0.1 for q in qs)).map(
        lambda qs: np.stack([quaternion_matrix(np.asarray(q) / np.linalg.norm(q)) for q in qs]))


def quaternion_matrix(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def arrays(shape):
    good = st.lists(finite, min_size=int(np.prod(shape)), max_size=int(np.prod(shape))).map(
        lambda v: np.asarray(v).reshape(shape))
    odd_shape = st.lists(finite, min_size=1, max_size=9).map(np.asarray)
    with_nonfinite = good.map(lambda a: np.where(np.arange(a.size).reshape(a.shape) == 0, np.nan, a))
    complex_values = good.map(lambda a: a * (1 + 1e-9j))
    return st.one_of(good, good, good, odd_shape, with_nonfinite, complex_values, st.just("text"), st.just(None))


@SETTINGS
@given(st.fixed_dictionaries({}, optional={
    "positions": arrays((2, 3)), "momenta": arrays((2, 3)), "angular_momenta": arrays((2, 3)),
    "attitudes": st.one_of(rotations(2), arrays((2, 3, 3))), "t": st.one_of(finite, wild)}))
def test_set_state_is_refused_whole_or_read_back_exactly(dumbbells, parts):
    sim = dumbbells_sim(dumbbells)
    before = state(sim)
    try:
        sim.set_state(**parts)
    except noether.Error as e:
        assert str(e)
        assert state(sim) == before, "a refused set_state changed the state"
        event(f"refused: {type(e).__name__}")
        return
    event("accepted")
    for name, value in parts.items():
        got = getattr(sim, name)
        if name == "t":
            assert got == value
        else:
            assert got.tobytes() == np.asarray(value, dtype=float).tobytes(), name
    # The state it took integrates (or fails as an IntegrationError), never crashes.
    try:
        sim.integrate(sim.t + 0.01) if math.isfinite(sim.t + 0.01) else None
    except (noether.IntegrationError, noether.SceneError):
        pass


@SETTINGS
@given(steps=st.integers(0, 40), more=st.integers(1, 20), spin=st.floats(-20, 20))
def test_save_and_load_give_the_same_state_and_the_same_future(dumbbells, tmp_path_factory, steps, more, spin):
    dumbbells["bodies"][0]["angular_velocity"] = [0, 0, spin]
    sim = noether.Simulation(dumbbells)
    h = dumbbells["integrator"]["step"]
    sim.integrate(steps * h)
    path = tmp_path_factory.mktemp("save") / "state.h5"
    sim.save(str(path))
    later = noether.Simulation.load(str(path))
    assert state(later) == state(sim)
    sim.integrate((steps + more) * h)
    later.integrate((steps + more) * h)
    assert state(later) == state(sim)
