"""What a killed run's output file must be (docs/reliability.md, "Kills"): a file that opens and
whose every object can be visited, every series holding at least /frames_complete frames (of
one length while the run writes; a kill while a finished run cuts them to their final length
may leave some cut and some not), its first /frames_complete frames complete and real; a
finished file (/work present) holds exactly its frames. Shared by sigkill.py and
kill_at_every_write.py, which write the dumbbells (examples/dumbbells.yaml) a frame every step.
"""
import h5py
import numpy as np

SERIES = ("step", "time", "value")


def check(path, h, E0, frames_full):
    """(the longest series' length, /frames_complete) of the file at `path`; raises if it is not
    a killed or finished run's file as above. `h`: the output interval, `E0` the energy,
    `frames_full` the frames of the finished run."""
    with h5py.File(path, "r", locking=False) as f:
        lengths = {}
        f.visititems(lambda name, obj: lengths.__setitem__(name, obj.shape[0])
                     if isinstance(obj, h5py.Dataset) and name.rsplit("/", 1)[-1] in SERIES
                     and not name.startswith("integrator") else None)
        assert len(lengths) >= 10, lengths  # step and time are hard links: visited once
        n = int(f["frames_complete"][()])
        assert 0 <= n <= min(lengths.values()), f"/frames_complete {n} beyond a series: {lengths}"
        step = f["particles/bodies/position/step"][:n]
        tt = f["particles/bodies/position/time"][:n]
        assert np.array_equal(step, np.arange(n)), "steps"
        assert np.allclose(tt, h * np.arange(n), rtol=0, atol=1e-9), "times"
        for name in lengths:
            values = f[name][:n]
            if name.startswith("observables/osculating_elements"):  # NaN by design for an unbound pair
                values = values[np.isfinite(values[:, 0])] if values.ndim == 2 else values
            if name.startswith("observables/nutation_angle"):  # NaN by design for a body that does not rotate
                values = values[np.linalg.norm(f["particles/bodies/angular_momentum/value"][:n], axis=2) > 0]
            assert np.all(np.isfinite(values)), f"{name}: a non-finite value in a complete frame"
        energy = f["observables/energy/value"][:n]
        assert np.all(np.abs(energy - E0) < 1e-6), "energies of complete frames"
        if "work" in f:  # the run reached its end: every frame is there, every series that long
            assert set(lengths.values()) == {n} and n == frames_full, (n, lengths, frames_full)
            assert f["work"].attrs["outcome"] == "completed", f["work"].attrs["outcome"]
        return max(lengths.values()), n
