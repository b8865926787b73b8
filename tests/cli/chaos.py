"""chaos.py NOETHER SOURCE_DIR WORK_DIR: `noether run --chaos`, the spin states, and the ensemble's
indicator columns (docs/derivatives.md, "Chaos indicators"; docs/user-guide.md, "Spin state";
docs/ensembles.md) as a user meets them.

The tumbling moon's MEGNO grows far beyond 2 while the same moon started synchronous on a
circular orbit stays near 2; the file's /derivatives/megno and /derivatives/fli end at the
summary's values; an ensemble over the moon's eccentricity writes /indicators/{megno,fli,lyapunov}
and the spin states' columns equal to those of `noether run` with each sample's overrides;
such a run stopped half-way and resumed ends with the uninterrupted run's indicators.
"""
import json
import os
import subprocess
import sys

import h5py
import numpy as np

noether, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
t_end = 150 if len(sys.argv) > 4 and sys.argv[4] == "light" else 300  # light: under the sanitizers
os.makedirs(work, exist_ok=True)
os.chdir(work)
scene = os.path.join(src, "examples", "tumbling-moon.yaml")
base = ["--no-progress", "--force", "--summary", "json", "--set", f"run.t_end={t_end}", "--set", "run.output_every=10"]


def run(*extra, output="chaos.h5", what="chaos"):
    done = subprocess.run([noether, "run", scene, "--chaos", "-o", output, *base, *extra], check=True,
                          capture_output=True, text=True)
    return json.loads(done.stdout)[what]


tumbling = run()
assert tumbling["megno"] > 5 and tumbling["t"] == t_end and not tumbling["overflowed"], tumbling
with h5py.File("chaos.h5", "r") as f:
    megno, fli = f["derivatives/megno/value"][:], f["derivatives/fli/value"][:]
    assert np.array_equal(f["derivatives/megno/time"][:], f["particles/bodies/position/time"][:])
assert megno.shape == (t_end // 10 + 1,) and np.isnan(megno[0]), megno
assert megno[-1] == tumbling["megno"] and fli[-1] == tumbling["fli"], (megno[-1], fli[-1], tumbling)
assert np.all(np.diff(fli[1:]) >= 0), fli

regular = run("--set", "bodies.moon.orbit.e=0", "--set", "bodies.moon.angular_velocity=[0,0,1.02]")
assert abs(regular["megno"] - 2) < 0.1, regular

# The ensemble's columns are the runs' own numbers.
subprocess.run([noether, "ensemble", scene, "--set", "run.chaos=true", "--set", f"run.t_end={t_end}",
                "--set", "run.output_every=0.05", "--vary", "bodies.moon.orbit.e=grid(0,0.1,3)", "-o", "ensemble.h5",
                "--force"], check=True, capture_output=True, text=True)
with h5py.File("ensemble.h5", "r") as f:
    e = f["inputs/bodies.moon.orbit.e"][:]
    columns = {k: f["indicators/" + k][:] for k in ("megno", "fli", "lyapunov")}
    spin_columns = {k: f["indicators/moon." + k][:] for k in ("libration_amplitude", "turns", "max_pitch", "max_roll",
                                                               "max_nutation")}
    assert f["indicators/megno"].attrs["unit"] in (b"1", "1")
    assert f["indicators/moon.max_nutation"].attrs["unit"] in (b"deg", "deg")
for i, ecc in enumerate(e):
    done = subprocess.run([noether, "run", scene, "--chaos", *base, "--set", "run.output_every=0.05", "--set",
                           f"bodies.moon.orbit.e={ecc!r}"], check=True, capture_output=True, text=True)
    summary = json.loads(done.stdout)
    for k, values in columns.items():
        expected = summary["chaos"][k]
        assert abs(values[i] - expected) <= 1e-12 * abs(expected), (i, k, values[i], expected)
    moon = next(s for s in summary["spin_states"] if s["body"] == "moon")
    assert moon["other"] == "planet", moon
    for k, values in spin_columns.items():
        expected = moon[k]
        assert expected is not None and values[i] == expected, (i, k, values[i], expected)

# --resume: the tumbling moon stopped half-way and continued ends with the indicators of the run
# straight through, to the bit (docs/derivatives.md, "Continuing").
run("--set", f"run.t_end={t_end // 2}", output="half.h5")
resumed = subprocess.run([noether, "run", "--resume", "half.h5", "--t-end", str(t_end), "--no-progress", "--summary",
                          "json"], check=True, capture_output=True, text=True)
assert json.loads(resumed.stdout)["chaos"] == tumbling, (json.loads(resumed.stdout)["chaos"], tumbling)
print("chaos: tumbling <Y> =", tumbling["megno"], "regular <Y> =", regular["megno"])
