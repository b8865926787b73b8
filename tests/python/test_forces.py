"""Forces beyond the potential from Python (docs/forces.md): a scene's tides through
noether.Simulation — the summary's per-force work and momenta, the file's force balance read back
by noether.read, and E − W against E0 from the frames, which errs as the LGVI does without the
tide."""
import numpy as np
import pytest

import noether


def test_tides_balance_in_the_summary_and_the_file(source, tmp_path):
    out = tmp_path / "tides.h5"
    sim = noether.Simulation(source / "examples" / "tidal-spin-down.yaml", set=["run.t_end=20"], output=out)
    sim.integrate(20)
    summary = sim.finish()
    forces = summary["forces"]
    assert [f["name"] for f in forces] == ["tides planet"]
    W = forces[0]["work"]
    assert W < 0  # the tide dissipates
    assert np.linalg.norm(forces[0]["angular_momentum"]) < 1e-15  # internal: ΔL is round-off
    run = noether.read(out)
    balance = run["force_balance"]  # [frame][force][7]: W, ΔP, ΔL
    assert balance.shape[1:] == (1, 7)
    assert balance[-1, 0, 0] == pytest.approx(W, rel=1e-15)
    E = run["energy"]
    drift = np.abs(E - balance[:, 0, 0] - E[0]).max()
    assert drift == pytest.approx(summary["max_abs_energy_error"], rel=1e-12)
    # E − W errs as much as E alone does without the tide: the LGVI's own energy error.
    alone = noether.Simulation(source / "examples" / "tidal-spin-down.yaml", set=["run.t_end=20", "forces.0.k2=0"])
    alone.integrate(20)
    assert drift < 1.5 * alone.finish()["max_abs_energy_error"]
