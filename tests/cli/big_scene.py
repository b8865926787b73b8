"""big_scene.py NOETHER WORK_DIR: a 1,000-body scene (over 64 KiB of YAML) writes its output
with -o, and h5py reads its masses, names, G, units and the scene, as given and as run, without any
YAML (docs/user-guide.md, "Output"). Fails on a writer that stores the scene as an attribute
(HDF5 refuses attributes over 64 KiB) or ignores --set in what it stores."""
import os
import re
import subprocess
import sys

import h5py
import numpy as np

noether, work = sys.argv[1], sys.argv[2]
os.makedirs(work, exist_ok=True)
os.chdir(work)
n = 1000
masses = 1.0 + np.arange(n) % 7 / 8.0
lines = ["# 1,000 point masses of ~1 kg on a 10 x 10 x 10 km lattice: a scene over 64 KiB.",
         "units: {length: km, mass: kg, time: s}", "bodies:"]
for i in range(n):
    x, y, z = i % 10, (i // 10) % 10, i // 100
    lines.append(f"  - {{name: body-{i:04d}, mass: {masses[i]!r}, position: [{x}, {y}, {z}], "
                 f"velocity: [0, 0, 0]}}  # a comment to make the file as large as real ones are")
lines += ["potential: {plugin: point-mass}", "integrator: {plugin: lgvi, step: 0.01}",
          "run: {t_end: 0.05, output_every: 0.01}", ""]
text = "\n".join(lines)
assert len(text.encode()) > 65536, len(text)
with open("big.yaml", "w") as f:
    f.write(text)

subprocess.run([noether, "run", "big.yaml", "--no-progress", "--force", "-o", "big.h5",
                "--set", "bodies.body-0007.mass=2.5"], check=True, stdout=subprocess.DEVNULL)
masses[7] = 2.5
with h5py.File("big.h5", "r") as f:
    bodies = f["particles/bodies"]
    names = [s.decode() if isinstance(s, bytes) else s for s in bodies["name"][()]]
    assert names == [f"body-{i:04d}" for i in range(n)], names[:3]
    assert np.array_equal(bodies["mass"][()], masses), "masses (with the --set override)"
    assert abs(float(f["parameters"].attrs["G"]) / 6.67430e-20 - 1) < 1e-14  # CODATA 2018 in km, kg, s
    assert bodies["mass"].attrs["unit"] == "kg" and bodies["position/value"].attrs["unit"] == "km"
    assert bodies["velocity/value"].attrs["unit"] == "km/s"
    assert f["observables/energy/value"].attrs["unit"] == "kg km^2/s^2"
    assert f["parameters/scene"][()].decode() == text, "the scene as given"
    as_run = f["parameters/scene_as_run"][()].decode()
    assert re.search(r"name: body-0007\n\s+mass: 2\.5\n", as_run), as_run[:600]
    assert bodies["position/value"].shape == (6, n, 3)
    assert int(f["frames_complete"][()]) == 6
print(f"big_scene: {n} bodies, scene {len(text)} bytes: masses, names, G and the scene read back")
