"""The pytest suite of the Python module (tests/CMakeLists.txt runs it from ctest, with
PYTHONPATH at the build tree's module and NOETHER_EXE / NOETHER_SOURCE_DIR set)."""
import os
import pathlib

import pytest

SOURCE = pathlib.Path(os.environ.get("NOETHER_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
NOETHER = os.environ.get("NOETHER_EXE", "noether")


@pytest.fixture
def source():
    return SOURCE


@pytest.fixture
def noether_exe():
    return NOETHER


# The dumbbells of Lee, Leok & McClamroch 2007 §5 as Python data: examples/dumbbells.yaml's keys.
DUMBBELLS = {
    "G": 0.2222222222222222,
    "bodies": [
        {"name": "alpha", "mass": 1.5, "inertia": [0.0004, 0.0238, 0.0238], "position": [0.67, 0, 0.2],
         "velocity": [0, 0.67, 0], "angular_velocity": [0, 0, 9], "shape": {"dumbbell": {"length": 0.25}}},
        {"name": "beta", "mass": 3, "inertia": [0.0030, 0.1905, 0.1905], "position": [-0.33, 0, -0.1],
         "velocity": [0, -0.33, 0], "angular_velocity": [0, 0, 0], "shape": {"dumbbell": {"length": 0.5}}},
    ],
    "potential": {"plugin": "sphere-cluster"},
    "integrator": {"plugin": "lgvi", "step": 0.0002},
    "run": {"t_end": 20, "output_every": 0.01},
}


@pytest.fixture
def dumbbells():
    import copy
    return copy.deepcopy(DUMBBELLS)
