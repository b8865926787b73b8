"""export.py NOETHER SOURCE_DIR WORK_DIR: the data of pictures of runs, without a browser (so that
the sanitizer job runs it; tests/cli/view.py draws the pages in Chromium): the frames a
`noether view` page holds, and `noether export --format vtk` read back by meshio, an independent
reader of VTK XML files (Debian's python3-meshio; docs/visualisation.md).

A page's NOETHER_RUN holds the file's positions bit for bit (float64) and its exact attitudes as
float32 quaternions (to 1e-7), at the frames it names, with their times; a polyhedron's mesh as
float32.

Each .vtu of a collection holds, for its frame, every body where the HDF5 file puts it: a
polyhedron's vertices are x + R v (v the file's mesh in the body frame, R the exact attitude)
to round-off and its triangles the file's faces; an ellipsoid's vertices lie on the ellipsoid
x + R diag(a) S² (|diag(a)⁻¹ Rᵀ(p − x)| = 1 to 1e-12) with 20·4^level triangles; a dumbbell's
on its two spheres; a point mass is one vertex at its position. The collection's times and the
files' TimeValue are the frames' times; --max-frames keeps evenly spaced frames, first and last
among them; --force replaces an earlier export; what is not an earlier export is never
replaced; bad options are refused and leave nothing behind.
"""
import base64
import json
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy as np

from run_geometry import Run, run_scene

noether, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)


def run(scene, name, *sets):
    return run_scene(noether, src, work, scene, name, *sets)


def export(h5, *extra, expect=0):
    p = subprocess.run([noether, "export", h5, *extra], capture_output=True, text=True)
    assert p.returncode == expect, f"export {h5} {extra}: exit {p.returncode}\n{p.stdout}\n{p.stderr}"
    return p


def collection(pvd):
    """(time, file) of each data set of a .pvd, in order."""
    root = ET.parse(pvd).getroot()
    assert root.get("type") == "Collection"
    return [(float(d.get("timestep")), os.path.join(os.path.dirname(pvd), d.get("file"))) for d in root.iter("DataSet")]


def check(h5, pvd, frames, level=4):
    """Every file of the collection against the run: returns the number of frames checked."""
    r = Run(h5)
    sets = collection(pvd)
    assert [int(re.search(r"frame-(\d+)\.vtu$", f).group(1)) for _, f in sets] == frames
    for (t, f), k in zip(sets, frames):
        assert t == r.t[k], (t, r.t[k])
        m = meshio.read(f)
        assert m.field_data["TimeValue"][0] == r.t[k]
        body = m.point_data["body"]
        assert sorted(set(body)) == list(range(len(r.names)))
        cells = {c.type: c for c in m.cells}
        for j, name in enumerate(r.names):
            p = m.points[body == j]
            first = np.flatnonzero(body == j)[0]
            x = r.x[k, j]
            if j not in r.R:  # a point mass: one vertex
                assert len(p) == 1 and np.array_equal(p[0], x), (name, p, x)
                continue
            local = (p - x) @ r.R[j][k]  # Rᵀ (p − x), each row
            scale = np.abs(x).max() + np.abs(local).max()
            if r.kinds[j] == "polyhedron":
                v, faces = r.meshes[j]
                assert np.abs(p - (x + v @ r.R[j][k].T)).max() <= 1e-12 * scale, name
                tri = cells["triangle"].data
                mine = tri[np.isin(tri[:, 0], np.flatnonzero(body == j))] - first
                assert np.array_equal(mine, faces), name
            elif r.kinds[j] == "ellipsoid":
                radius = np.linalg.norm(local / r.semi_axes[j], axis=1)
                assert np.abs(radius - 1).max() < 1e-12 * scale / r.semi_axes[j].min(), (name, np.abs(radius - 1).max())
                tri = cells["triangle"].data
                assert np.isin(tri[:, 0], np.flatnonzero(body == j)).sum() == 20 * 4**level
            elif r.kinds[j] == "dumbbell":
                L = r.dumbbell[j]
                d = np.minimum(np.linalg.norm(local - [L / 2, 0, 0], axis=1), np.linalg.norm(local + [L / 2, 0, 0], axis=1))
                assert np.abs(d - L / 10).max() < 1e-12 * scale, name
                assert np.abs(np.linalg.norm(local - [L / 2, 0, 0], axis=1) - L / 10).min() < 1e-12 * scale
                assert np.abs(np.linalg.norm(local + [L / 2, 0, 0], axis=1) - L / 10).min() < 1e-12 * scale
    return len(sets)


def page_data(html):
    """The NOETHER_RUN object of a page, its typed arrays decoded."""
    text = open(html, encoding="utf-8").read()
    data = json.loads(re.search(r"<script>const NOETHER_RUN = (\{.*?\});</script>", text, re.S).group(1))
    arrays = {"t": "<f8", "x": "<f8", "q": "<f4", "frame_index": "<u4"}
    return data, {k: np.frombuffer(base64.b64decode(data[k]), dtype) for k, dtype in arrays.items()}


def check_page(h5, max_frames):
    html = os.path.join(work, "page.html")
    p = subprocess.run([noether, "view", h5, "-o", html, "--force", "--max-frames", str(max_frames)], capture_output=True,
                       text=True)
    assert p.returncode == 0, p.stderr
    r = Run(h5)
    data, a = page_data(html)
    frames = a["frame_index"]
    n = len(r.names)
    assert np.array_equal(frames, [round(i * (len(r.t) - 1) / (max_frames - 1)) for i in range(max_frames)])
    assert np.array_equal(a["t"], r.t[frames])
    assert np.array_equal(a["x"].reshape(-1, n, 3), r.x[frames])
    q = a["q"].reshape(len(frames), -1, 4)
    for j, body in enumerate(data["bodies"]):
        kind = r.kinds.get(j, "point")
        assert body["name"] == r.names[j] and body["shape"]["kind"] == {"dumbbell": "spheres"}.get(kind, kind)
        if j not in r.R:
            continue
        x, y, z, w = q[:, body["rigid"]].T.astype(float)  # R of the quaternion, each frame
        R = np.stack([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                      [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                      [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]).transpose(2, 0, 1)
        assert np.abs(R - r.R[j][frames]).max() < 1e-6, np.abs(R - r.R[j][frames]).max()
        if r.kinds[j] == "polyhedron":
            v = np.frombuffer(base64.b64decode(body["shape"]["vertices"]), "<f4").reshape(-1, 3)
            f = np.frombuffer(base64.b64decode(body["shape"]["faces"]), "<u4").reshape(-1, 3)
            assert np.array_equal(v, r.meshes[j][0].astype(np.float32)) and np.array_equal(f, r.meshes[j][1])
    return len(frames)


# KW4 as the radar polyhedra, decimated to 10 of its 49 frames.
h5 = run("kw4-polyhedra.yaml", "kw4-polyhedra", "run.t_end=28800", "run.output_every=600")
print("KW4 polyhedra page:", check_page(h5, 7), "frames hold the file's positions and attitudes")
pvd = os.path.join(work, "kw4.pvd")
p = export(h5, "-o", pvd, "--max-frames", "10", "--force")
assert re.match(r"export: .*kw4\.pvd and .*kw4/ \(10 of 49 frames, [\d.]+ MB\)", p.stdout), p.stdout
assert "decimated: 10 of the file's 49 frames" in p.stderr, p.stderr
print("KW4 polyhedra:", check(h5, pvd, [round(i * 48 / 9) for i in range(10)]), "frames match the HDF5 file")

# Replaced with --force: the old frames go.
p = export(h5, "-o", pvd, "--max-frames", "3", expect=2)
assert "kw4.pvd exists; noether does not overwrite output unless asked: pass --force" in p.stderr, p.stderr
export(h5, "-o", pvd, "--max-frames", "3", "--force")
assert sorted(os.listdir(os.path.join(work, "kw4"))) == ["frame-00.vtu", "frame-24.vtu", "frame-48.vtu"]
check(h5, pvd, [0, 24, 48])

# KW4 as ellipsoids (tessellation 3), the dumbbells, the figure-eight (point masses).
h5 = run("kw4-ellipsoids.yaml", "kw4-ellipsoids", "run.t_end=36000", "run.output_every=1800")
export(h5, "--tessellation", "3", "--force")
print("KW4 ellipsoids:", check(h5, h5[:-3] + ".pvd", list(range(21)), level=3), "frames")
h5 = run("dumbbells.yaml", "dumbbells", "run.t_end=1")
export(h5, "--max-frames", "5", "--force")
print("dumbbells:", check(h5, h5[:-3] + ".pvd", [0, 25, 50, 75, 100]), "frames")
print("dumbbells page:", check_page(h5, 4), "frames")
h5 = run("figure-eight.yaml", "figure-eight")
print("figure-eight page:", check_page(h5, 3), "frames")
export(h5, "--max-frames", "4", "--force")
print("figure-eight:", check(h5, h5[:-3] + ".pvd", [0, 333, 667, 1000]), "frames")

# Refusals, with nothing left behind: a folder that is not an earlier export, a bad name, format
# or tessellation, an ensemble's file.
foreign = os.path.join(work, "mine")
os.makedirs(foreign, exist_ok=True)
open(os.path.join(foreign, "notes.txt"), "w").write("mine\n")
p = export(h5, "-o", foreign + ".pvd", "--force", expect=2)
assert "holds files noether export did not write" in p.stderr, p.stderr
assert os.listdir(foreign) == ["notes.txt"] and not os.path.exists(foreign + ".pvd")
p = export(h5, "-o", os.path.join(work, "x.vtu"), expect=2)
assert "a ParaView collection's name ends in .pvd" in p.stderr, p.stderr
p = export(h5, "--format", "gltf", expect=2)
assert "--format gltf: the formats are vtk" in p.stderr, p.stderr
p = export(h5, "--tessellation", "7", expect=2)
assert "--tessellation" in p.stderr, p.stderr
ens = os.path.join(work, "ens.h5")
q = subprocess.run([noether, "ensemble", os.path.join(src, "examples", "dumbbells.yaml"), "--vary",
                    "bodies.alpha.mass=list(1.5, 1.6)", "--samples", "2", "--set", "run.t_end=0.1", "-o", ens, "--force"],
                   capture_output=True, text=True)
assert q.returncode == 0, q.stderr
p = export(ens, expect=2)
assert "is an ensemble's file" in p.stderr, p.stderr
assert not os.path.exists(os.path.join(work, "ens.pvd")) and not os.path.exists(os.path.join(work, "ens"))
assert not [f for f in os.listdir(work) if ".partial-" in f], os.listdir(work)
print("export: all checks passed")
