"""noether.stokes (docs/gravity-fields.md): a body's Stokes coefficients from Python, against the
closed forms of a homogeneous ellipsoid and against `noether shape stokes`'s file."""
import math
import subprocess

import numpy as np
import pytest

import noether


def test_ellipsoid_against_its_closed_forms(source):
    """KW4 Beta's ellipsoid (a, b, c) = (285, 231.5, 174.5) m: unnormalised C20 = (2c² − a² − b²)/(10R²),
    C22 = (a² − b²)/(20R²), C40 = 3(3a⁴ + 3b⁴ + 8c⁴ + 2a²b² − 8a²c² − 8b²c²)/(280R⁴), odd and sine terms 0."""
    a, b, c = 285.0, 231.5, 174.5
    R = 300.0
    s = noether.stokes(source / "examples" / "kw4-ellipsoids.yaml", "beta", degree=4, radius=R, normalized=False)
    assert s["degree"] == 4 and not s["normalized"] and s["reference_radius"] == R
    assert s["mass"] == pytest.approx(1.35e11, rel=1e-14)
    assert s["gm"] == pytest.approx(6.674e-11 * 1.35e11, rel=1e-14)
    C, S = s["C"], s["S"]
    assert C.shape == (5, 5)
    assert C[2, 0] == pytest.approx((2 * c * c - a * a - b * b) / (10 * R * R), rel=1e-13)
    assert C[2, 2] == pytest.approx((a * a - b * b) / (20 * R * R), rel=1e-13)
    assert C[4, 0] == pytest.approx(3 * (3 * a**4 + 3 * b**4 + 8 * c**4 + 2 * a * a * b * b - 8 * a * a * c * c
                                         - 8 * b * b * c * c) / (280 * R**4), rel=1e-12)
    assert np.max(np.abs(S)) < 1e-16 and abs(C[3, 1]) < 1e-16 and abs(C[2, 1]) < 1e-16
    # C/(M R²) of the ellipsoid: (a² + b²)/(5R²)
    assert s["polar_moment"] == pytest.approx((a * a + b * b) / (5 * R * R), rel=1e-13)
    normalized = noether.stokes(source / "examples" / "kw4-ellipsoids.yaml", "beta", degree=4, radius=R)
    assert normalized["C"][2, 2] == pytest.approx(C[2, 2] / math.sqrt(2 * 5 * 1 / 24), rel=1e-13)  # (31.2)


def test_same_as_the_command(source, noether_exe, tmp_path):
    out = tmp_path / "beta.gfc"
    subprocess.run([noether_exe, "shape", "stokes", str(source / "examples" / "kw4-ellipsoids.yaml"), "--body", "beta",
                    "--degree", "6", "-o", str(out)], check=True, capture_output=True)
    rows = [l.split() for l in out.read_text().splitlines() if l.startswith("gfc")]
    s = noether.stokes(source / "examples" / "kw4-ellipsoids.yaml", "beta", degree=6)
    for _, n, m, c, sn in rows:
        assert float(c) == s["C"][int(n), int(m)] and float(sn) == s["S"][int(n), int(m)]


def test_refusals(source):
    with pytest.raises(noether.SceneError, match="no body named 'gamma'"):
        noether.stokes(source / "examples" / "kw4-ellipsoids.yaml", "gamma")
    with pytest.raises(noether.SceneError, match="given by its field to degree 8"):
        noether.stokes(source / "examples" / "kw4-field-secondary.yaml", "beta", degree=10)
