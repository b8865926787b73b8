"""initial_states.py NOETHER SOURCE_DIR: scene units and initial states given as osculating
elements or relative to another body (docs/user-guide.md "Units", "Initial states").

1. examples/kw4-elements.yaml (Beta's published elements about Alpha) gives the relative state
   Ho et al. 2021 published for those elements, to the digits they printed.
2. One system written in SI and in km, kg, h (the numbers converted by this test, G left to the
   declared units) gives the same trajectory once the output is converted with its own `unit`
   attributes; and in au, M_sun, day the default G is Gauss's constant squared.
3. `relative_to` adds the other body's state; the elements read back from the written state are
   the ones given (an independent inverse, eqs. 17.5-17.8, written here in Python)."""
import math
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

noether, src = sys.argv[1], sys.argv[2]
tmp = tempfile.mkdtemp()


def run(scene, *args, text=None):
    if text is not None:
        scene = os.path.join(tmp, scene)
        with open(scene, "w") as f:
            f.write(text)
    out = os.path.join(tmp, os.path.basename(scene) + ".h5")
    subprocess.run([noether, "run", scene, "-o", out, "--force", "--no-progress", *args], check=True,
                   capture_output=True)
    return h5py.File(out, "r")


# 1. The published conversion (Ho et al. 2021): relative state printed to 1 mm and 1 µm/s.
with run(f"{src}/examples/kw4-elements.yaml", "--set", "run.t_end=3600") as f:
    x = f["particles/bodies/position/value"][0]
    v = f["particles/bodies/velocity/value"][0]
    m = f["particles/bodies/mass"][:]
    assert f["particles/bodies/position/value"].attrs["unit"] == "m"
    assert f["particles/bodies/velocity/value"].attrs["unit"] == "m/s"
dr = (x[1] - x[0]) - np.array([-1967.873, 1472.801, -667.415])
dv = (v[1] - v[0]) - np.array([0.127814, 0.206537, 0.078911])
assert np.abs(dr).max() <= 0.5e-3 and np.abs(dv).max() <= 0.5e-6, (dr, dv)
# barycentric: true puts the barycentre at rest at the origin
assert np.abs(m @ x).max() < 1e-12 * (m @ np.abs(x)).max() and np.abs(m @ v).max() < 1e-12 * (m @ np.abs(v)).max()

# 2. The same system in two unit systems.
template = """units: {units}
bodies:
  - name: rock
    density: {density!r}
    shape: {{ellipsoid: {{semi_axes: [{a1!r}, {a2!r}, {a3!r}]}}}}
    position: [0, 0, 0]
    angular_velocity: [0, {w1!r}, {w2!r}]
  - name: moon
    mass: {mass!r}
    orbit: {{around: rock, a: {a!r}, e: 0.2, i: 30, Omega: 40, omega: 50, nu: 60}}
potential: {{plugin: mutual-series, order: 2}}
integrator: {{plugin: lgvi, step: {h!r}}}
run: {{t_end: {t_end!r}, output_every: {every!r}}}
"""
L, T = 1000.0, 3600.0  # one km in m, one hour in s
si = dict(units="SI", density=2000.0, a1=800.0, a2=600.0, a3=500.0, w1=1e-4, w2=5e-4, mass=1e11, a=3000.0,
          h=60.0, t_end=86400.0, every=21600.0)
kmh = dict(si, units="{length: km, mass: kg, time: h}", density=2000.0 * L**3, a1=0.8, a2=0.6, a3=0.5,
           w1=1e-4 * T, w2=5e-4 * T, a=3.0, h=60.0 / T, t_end=24.0, every=6.0)
scale = {"m": 1.0, "km": L, "s": 1.0, "h": T, "kg": 1.0, "1": 1.0}


def to_si(dataset):
    unit = dataset.attrs["unit"]
    num, _, den = unit.partition("/")
    factor = math.prod(scale[u] for u in num.split()) / (scale[den] if den else 1.0)
    return dataset[:] * factor


with run("si.yaml", text=template.format(**si)) as a, run("kmh.yaml", text=template.format(**kmh)) as b:
    assert b["particles/bodies/position/value"].attrs["unit"] == "km"
    assert b["particles/bodies/velocity/value"].attrs["unit"] == "km/h"
    assert a["parameters"].attrs["G"] == 6.67430e-11
    assert abs(b["parameters"].attrs["G"] - 6.67430e-11 * T**2 / L**3) <= 1e-15 * b["parameters"].attrs["G"]
    for name in ["position", "velocity"]:
        ref, got = to_si(a[f"particles/bodies/{name}/value"]), to_si(b[f"particles/bodies/{name}/value"])
        assert ref.shape == got.shape == (5, 2, 3)
        err = np.abs(got - ref).max() / np.abs(ref).max()
        assert err < 1e-11, (name, err)
    assert np.abs(to_si(b["particles/bodies/position/time"]) - a["particles/bodies/position/time"][:]).max() < 1e-6

solar = template.format(**dict(si, units="{length: au, mass: M_sun, time: day}", density=1.0, mass=3e-6, a=1.0,
                               a1=8e-3, a2=6e-3, a3=5e-3, h=1.0, t_end=10.0, every=10.0))
with run("solar.yaml", text=solar) as f:
    k = 0.01720209895  # Gauss's gravitational constant, au^{3/2} M_sun^{-1/2} day^{-1}
    assert abs(f["parameters"].attrs["G"] / k**2 - 1.0) < 1e-10, f["parameters"].attrs["G"]
    assert f["parameters"].attrs["unit_G"] == "au^3/(M_sun day^2)"


# 3. relative_to, and the elements read back.
def elements(r, v, mu):
    h = np.cross(r, v)
    e_vec = np.cross(v, h) / mu - r / np.linalg.norm(r)
    a = 1.0 / (2.0 / np.linalg.norm(r) - v @ v / mu)
    n = np.cross([0.0, 0.0, 1.0], h)
    i = math.degrees(math.acos(h[2] / np.linalg.norm(h)))
    Omega = math.degrees(math.atan2(n[1], n[0])) % 360
    cos_w = n @ e_vec / (np.linalg.norm(n) * np.linalg.norm(e_vec))
    omega = math.degrees(math.acos(cos_w))
    omega = omega if e_vec[2] >= 0 else 360 - omega
    cos_nu = e_vec @ r / (np.linalg.norm(e_vec) * np.linalg.norm(r))
    nu = math.degrees(math.acos(np.clip(cos_nu, -1, 1)))
    nu = nu if r @ v >= 0 else 360 - nu
    return a, np.linalg.norm(e_vec), i, Omega, omega, nu


relative = """G: 2.0
bodies:
  - {name: star, mass: 3.0, position: [1, 2, 3], velocity: [0.1, 0.2, 0.3]}
  - {name: planet, mass: 1.0e-3, relative_to: star, position: [2, 0, 0], velocity: [0, 1, 0]}
  - name: moon
    mass: 1.0e-6
    orbit: {around: planet, a: 0.01, e: 0.7, i: 120, Omega: 200, omega: 300, M: 250}
potential: {plugin: point-mass}
integrator: {plugin: rk, method: rk4, step: 1e-4}
run: {t_end: 1e-3, output_every: 1e-3}
"""
with run("relative.yaml", text=relative) as f:
    x = f["particles/bodies/position/value"][0]
    v = f["particles/bodies/velocity/value"][0]
    assert f["parameters"].attrs["G"] == 2.0 and f["parameters"].attrs["unit_length"] == "L"
assert np.array_equal(x[1], [3.0, 2.0, 3.0]) and np.allclose(v[1], [0.1, 1.2, 0.3], rtol=0, atol=1e-15)
a, e, i, Omega, omega, nu = elements(x[2] - x[1], v[2] - v[1], 2.0 * (1.0e-3 + 1.0e-6))
assert abs(a / 0.01 - 1) < 1e-12 and abs(e - 0.7) < 1e-12, (a, e)
assert max(abs(i - 120), abs(Omega - 200), abs(omega - 300)) < 1e-9, (i, Omega, omega)
E = 2 * math.atan(math.sqrt(0.3 / 1.7) * math.tan(math.radians(nu) / 2))
M = math.degrees(E - 0.7 * math.sin(E)) % 360
assert abs(M - 250) < 1e-9, M
# No anomaly given: M = 0, the body at periapsis (r = a (1 − e)).
with run("periapsis.yaml", text=relative.replace(", M: 250}", "}")) as f:
    x = f["particles/bodies/position/value"][0]
    v = f["particles/bodies/velocity/value"][0]
assert abs(np.linalg.norm(x[2] - x[1]) / (0.01 * 0.3) - 1) < 1e-12, np.linalg.norm(x[2] - x[1])
assert abs((x[2] - x[1]) @ (v[2] - v[1])) < 1e-12 * np.linalg.norm(x[2] - x[1]) * np.linalg.norm(v[2] - v[1])
print("initial states and units: ok")
