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
    subprocess.run([sys.executable, child, scene, part, "1"], check=True)
    with h5py.File(full, "r") as a, h5py.File(part, "r") as b:
        assert int(b["frames_complete"][()]) == len(a["particles/bodies/position/time"])
        assert (np.diff(b["particles/bodies/position/time"][()]) > 0).all()  # every frame once
        for key in ["particles/bodies/position/value", "checkpoint/linear_momentum", "checkpoint/attitude",
                    "particles/bodies/angular_momentum/value", "observables/energy/value",
                    "particles/bodies/position/step"]:
            assert a[key][()].tobytes() == b[key][()].tobytes(), key
        assert b["work"].attrs["outcome"] == "completed"
