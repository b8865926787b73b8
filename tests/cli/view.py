"""view.py NOETHER SOURCE_DIR WORK_DIR: `noether view` pages drawn by headless Chromium (docs/visualisation.md).

Every page loads with no console error or warning and reports the frame it shows. In flat mode
(unlit pure colours, no antialiasing) the screenshot's pixels of each body are compared with an
independent drawing made here from the HDF5 file alone: positions, the exact attitudes
(/checkpoint/attitude) and the shapes (/parameters/shapes) projected through a pinhole camera
built from the page's address (camera, target, up, fov, size) as three.js defines it, and
rasterised at pixel centres. At two times:
- the silhouette of each ellipsoid, polyhedron and dumbbell matches the drawing here (overlap ≥ 0.97 of the
  union, centroid within 1.5 px);
- each body's centroid is its projected centre of mass within 2 px (ellipsoids, dots);
- KW4 Beta's silhouette area changes as it turns (by > 5 %), and Alpha's, seen from Alpha's own
  body frame, does not (< 0.5 %).
Recorded massless particles are white dots where their positions project, and the run's impulses
are reported with the frames nearest them. Also: a decimated page shows the frames it says, with their times; an ensemble's file, an existing
page and too few frames are refused with a message.
"""
import os
import re
import subprocess
import sys

import matplotlib.image
import numpy as np

noether, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
sys.path.insert(0, os.path.join(src, "tools"))
from open_view import browse as open_page  # noqa: E402
from run_geometry import Run, run_scene  # noqa: E402  (tests/cli, this script's folder)

W, H = 800, 600
profile = os.path.join(work, "chromium-profile")


def run(scene, name, *sets):
    return run_scene(noether, src, work, scene, name, *sets)


def view(h5, *extra):
    html = h5[:-3] + ".html"
    p = subprocess.run([noether, "view", h5, "-o", html, "--force", *extra], capture_output=True, text=True)
    assert p.returncode == 0, f"view {h5}: exit {p.returncode}\n{p.stderr}"
    assert re.match(r"view: .*\.html \(\d+ of \d+ frames, [\d.]+ MB\)", p.stdout), p.stdout
    return html, p


def browse(html, hash_, png=None):
    """The page's status (its JSON report) and, with png, its screenshot as an array [H][W][3]."""
    status = open_page(html, hash_, png, (W + 40, H + 160), profile)
    assert status["ready"], status
    assert not status["errors"] and not status["warnings"], f"{html}#{hash_}: {status['errors']} {status['warnings']}"
    if png is None:
        return status, None
    image = (matplotlib.image.imread(png)[:, :, :3] * 255).round().astype(int)
    assert status["width"] == W and status["height"] == H, status
    return status, image[:H, :W]


def camera_axes(status):
    eye, target, up = (np.array(status[k], float) for k in ("camera", "target", "up"))
    z = eye - target
    z /= np.linalg.norm(z)
    x = np.cross(up, z)
    x /= np.linalg.norm(x)
    return eye, x, np.cross(z, x), z


def project(points, status):
    """Pixel coordinates (column, row; origin at the top left corner) of points [k][3], as
    three.js's PerspectiveCamera after lookAt(target) with its up vector."""
    eye, x, y, z = camera_axes(status)
    d = np.atleast_2d(points) - eye
    depth = -(d @ z)
    assert np.all(depth > 0)
    f = 1 / np.tan(np.radians(status["fov"]) / 2)
    ndc_x = f / (W / H) * (d @ x) / depth
    ndc_y = f * (d @ y) / depth
    return np.column_stack([(ndc_x + 1) / 2 * W, (1 - ndc_y) / 2 * H])


def raster(triangles):
    """The pixels whose centres lie in any of the 2-D triangles [m][3][2]."""
    mask = np.zeros((H, W), bool)
    for a, b, c in triangles:
        lo = np.floor(np.minimum(np.minimum(a, b), c) - 0.5).astype(int)
        hi = np.ceil(np.maximum(np.maximum(a, b), c) - 0.5).astype(int)
        lo, hi = np.maximum(lo, 0), np.minimum(hi, [W - 1, H - 1])
        if np.any(hi < lo):
            continue
        X, Y = np.meshgrid(np.arange(lo[0], hi[0] + 1) + 0.5, np.arange(lo[1], hi[1] + 1) + 0.5)
        e = [(q[0] - p[0]) * (Y - p[1]) - (q[1] - p[1]) * (X - p[0]) for p, q in ((a, b), (b, c), (c, a))]
        inside = ((e[0] >= 0) & (e[1] >= 0) & (e[2] >= 0)) | ((e[0] <= 0) & (e[1] <= 0) & (e[2] <= 0))
        mask[lo[1]:hi[1] + 1, lo[0]:hi[0] + 1] |= inside
    return mask


def silhouette(run, k, j, status):
    """Body j's expected pixels at file frame k, and its centre of mass's pixel."""
    view = status["view"]
    turn = np.eye(3)
    if view.startswith("frame:"):
        turn = run.R[run.names.index(view.split(":", 1)[1])][k].T
    centre = turn @ (run.x[k, j] - run.origin(k, view))
    pixel = project(centre, status)[0]
    if j not in run.meshes:
        return None, pixel
    vertices, faces = run.meshes[j]
    world = centre + vertices @ (turn @ run.R[j][k]).T
    return raster(project(world, status)[faces]), pixel


def check_frame(run, html, hash_, name, silhouettes=True):
    """Draws the page at `hash_`; compares each body with the drawing here. Returns the areas."""
    status, image = browse(html, hash_, os.path.join(work, name + ".png"))
    k = status["file_frame"]
    assert status["time"] == run.t[k], (status["time"], run.t[k])
    areas = {}
    for j, body in enumerate(run.names):
        colour = np.array([(status["colours"][j] >> s) & 255 for s in (16, 8, 0)])
        seen = np.all(image == colour, axis=-1)
        expected, pixel = silhouette(run, k, j, status)
        if (expected is not None and not expected.any()) or (expected is None and not (0 <= pixel[0] < W and 0 <= pixel[1] < H)):
            assert not seen.any(), f"{name}: {body} is drawn where the camera does not see it"
            continue
        assert seen.sum() > 0, f"{name}: {body} is not in the picture"
        rows, cols = np.nonzero(seen)
        centroid = np.array([cols.mean() + 0.5, rows.mean() + 0.5])
        if expected is not None and silhouettes:
            overlap = (seen & expected).sum() / (seen | expected).sum()
            r, c = np.nonzero(expected)
            expected_centroid = np.array([c.mean() + 0.5, r.mean() + 0.5])
            print(f"{name}: {body}: {seen.sum()} px (expected {expected.sum()}), overlap {overlap:.4f}, "
                  f"centroid off by {np.linalg.norm(centroid - expected_centroid):.2f} px")
            assert overlap >= 0.97, f"{name}: {body}: overlap {overlap}"
            assert np.linalg.norm(centroid - expected_centroid) <= 1.5, (name, body, centroid, expected_centroid)
        if run.kinds.get(j) in (None, "ellipsoid"):  # dots and ellipsoids: symmetric about it
            print(f"{name}: {body}: centroid {centroid.round(2)}, centre of mass at {pixel.round(2)}")
            assert np.linalg.norm(centroid - pixel) <= 2.0, (name, body, centroid, pixel)
        areas[body] = seen.sum()
    return areas


flat = f"flat=1&hud=0&trails=0&size={W}x{H}"

# KW4 as ellipsoids: both silhouettes and centres of mass at two times, inertial and barycentric.
h5 = run("kw4-ellipsoids.yaml", "kw4-ellipsoids", "run.t_end=36000", "run.output_every=1800")
kw4e = Run(h5)
html, _ = view(h5)
for frame in (3, 14):
    check_frame(kw4e, html, f"{flat}&frame={frame}&camera=1500,-6000,9000&target=0,0,0&fov=30", f"kw4e-{frame}")
check_frame(kw4e, html, f"{flat}&frame=9&view=barycentric&camera=-4000,2500,6000&target=0,0,0&up=0,0,1&fov=35",
            "kw4e-barycentric")

# KW4 as the radar polyhedra: Beta's silhouette, seen close, changes as it turns (a quarter turn
# between frames 5 and 30); Alpha's, seen from its own body frame, does not.
h5 = run("kw4-polyhedra.yaml", "kw4-polyhedra", "run.t_end=28800", "run.output_every=600")
kw4p = Run(h5)
html, _ = view(h5)
camera = "camera=350,-900,600&target=0,0,0&up=0,0,1&fov=40"
a = check_frame(kw4p, html, f"{flat}&frame=5&view=centre:beta&{camera}", "kw4p-5")["beta"]
b = check_frame(kw4p, html, f"{flat}&frame=30&view=centre:beta&{camera}", "kw4p-30")["beta"]
print(f"Beta's silhouette: {a} px at frame 5, {b} px at frame 30")
assert abs(a - b) / max(a, b) > 0.05, (a, b)
camera = "camera=900,-2600,1800&target=0,0,0&up=0,0,1&fov=40"
a = check_frame(kw4p, html, f"{flat}&frame=5&view=frame:alpha&{camera}", "kw4p-frame-5")["alpha"]
b = check_frame(kw4p, html, f"{flat}&frame=30&view=frame:alpha&{camera}", "kw4p-frame-30")["alpha"]
print(f"Alpha in its own frame: {a} px at frame 5, {b} px at frame 30")
assert abs(a - b) / max(a, b) < 0.005, (a, b)

# Dumbbells (sphere clusters) and the figure-eight (dots): centres of mass.
h5 = run("dumbbells.yaml", "dumbbells", "run.t_end=2")
html, _ = view(h5)
check_frame(Run(h5), html, f"{flat}&frame=100&camera=0.3,-1.5,2.5&target=0,0,0&fov=35", "dumbbells")
h5 = run("figure-eight.yaml", "figure-eight")
html, _ = view(h5)
check_frame(Run(h5), html, f"{flat}&frame=250&camera=0,0,4&target=0,0,0&up=0,1,0&fov=40", "figure-eight")

# Every control's path with the page as a user sees it: lit, trails, labels, axes, playing, in
# a body frame; no console error or warning.
browse(html, "play=1&trail=50")
html, _ = view(os.path.join(work, "kw4-polyhedra.h5"))
browse(html, "view=frame:beta&axes=1")
h5 = run("kw4-field-secondary.yaml", "field", "run.t_end=7200")
html, _ = view(h5)
status, _ = browse(html, "view=barycentric")
assert status["frames_shown"] == 3, status

# Decimation: frames evenly spaced by index, the first and the last among them, with their times.
h5 = run("dumbbells.yaml", "dumbbells-long", "run.t_end=10")  # 1001 frames
html, p = view(h5, "--max-frames", "7")
assert "6 of" not in p.stdout and "(7 of 1001 frames" in p.stdout, p.stdout
assert "decimated: 7 of the file's 1001 frames" in p.stderr, p.stderr
t = Run(h5).t
for i in (0, 3, 6):
    status, _ = browse(html, f"frame={i}")
    assert status["file_frame"] == round(i * 1000 / 6) and status["time"] == t[status["file_frame"]], status
    assert status["frames_shown"] == 7

# An ensemble's samples in one page: each sample's Dimorphos where its own run puts it (in flat
# pictures each run's bodies have colours of their own); the page follows the first sample's frames.
ens = os.path.join(work, "dart.h5")
p = subprocess.run([noether, "ensemble", os.path.join(src, "examples", "didymos.yaml"), "--vary",
                    "bodies.dimorphos.velocity.1=list(0.1741158386581219, 0.14, 0.2)", "--samples", "3", "--trajectories",
                    "3", "--set", "run.t_end=14400", "--set", "run.output_every=600", "-o", ens, "--force"],
                   capture_output=True, text=True)
assert p.returncode == 0, p.stderr
page = os.path.join(work, "dart.html")
p = subprocess.run([noether, "view", ens, "--samples", "1,2", "-o", page, "--force"], capture_output=True, text=True)
assert p.returncode == 0 and "(25 of 25 frames, 2 runs," in p.stdout, p.stdout + p.stderr
samples = [Run(os.path.join(work, f"dart-sample-{i}.h5")) for i in (1, 2)]
status, image = browse(page, f"{flat}&frame=24&camera=0,-400,5000&target=0,0,0&up=0,1,0&fov=40",
                       os.path.join(work, "dart.png"))
assert [r["label"] for r in status["runs"]] == ["dart-sample-1.h5", "dart-sample-2.h5"], status["runs"]
for r, sample in enumerate(samples):
    j = sample.names.index("dimorphos")
    colour = np.array([(status["runs"][r]["colours"][j] >> s) & 255 for s in (16, 8, 0)])
    seen = np.all(image == colour, axis=-1)
    expected, pixel = silhouette(sample, 24, j, status)
    overlap = (seen & expected).sum() / (seen | expected).sum()
    print(f"dart sample {r + 1}: dimorphos {seen.sum()} px (expected {expected.sum()}), overlap {overlap:.4f}")
    assert overlap >= 0.97, overlap
p = subprocess.run([noether, "view", ens, "--samples", "2,7", "-o", page, "--force"], capture_output=True, text=True)
assert p.returncode == 2 and "dart-sample-7.h5 does not exist" in p.stderr and "--trajectories K" in p.stderr, p.stderr
p = subprocess.run([noether, "view", samples_file := os.path.join(work, "dart-sample-1.h5"), "--samples", "1", "-o", page,
                    "--force"], capture_output=True, text=True)
assert p.returncode == 2 and "is not an ensemble's file" in p.stderr, p.stderr
p = subprocess.run([noether, "view", samples_file, os.path.join(work, "kw4-polyhedra.h5"), "-o", page, "--force"],
                   capture_output=True, text=True)
assert p.returncode == 2 and "is a run of other bodies than" in p.stderr, p.stderr

# Massless particles and an impulse (issue 63, item 5): each recorded particle a white dot (flat
# mode) where its position in the file projects, unless a body hides it, and none elsewhere;
# particles=0 hides them; the impulse is reported with the frame nearest it (a mark on the slider).
cloud_h5 = run("didymos-particles.yaml", "particles", "run.t_end=7200",
               "impulses=[{body: dimorphos, time: 3600, delta_v: [0, -0.0027, 0]}]")
cloud_html, _ = view(cloud_h5)
cloud = Run(cloud_h5)
import h5py  # noqa: E402
with h5py.File(cloud_h5, "r") as f:
    particle_x = f["particles/test_particles/position/value"][:]
camera = "camera=0,-800,6000&target=0,0,0&up=0,1,0&fov=45&view=centre:didymos"
status, image = browse(cloud_html, f"{flat}&frame=10&{camera}", os.path.join(work, "particles.png"))
assert status["particles"] == 24 and status["impulses"] == [{"t": 3600, "body": "dimorphos", "frame": 6}], status
k = status["file_frame"]
hidden = np.zeros((H, W), bool)
for j in range(len(cloud.names)):
    expected, _ = silhouette(cloud, k, j, status)
    if expected is not None:
        hidden |= expected
pixels = project(particle_x[k] - cloud.x[k, cloud.names.index("didymos")], status)
visible = [p for p in pixels if 2 <= p[0] < W - 2 and 2 <= p[1] < H - 2 and not hidden[int(p[1]), int(p[0])]]
white = np.all(image == 255, axis=-1)
for p in visible:
    c, r = int(p[0]), int(p[1])
    assert white[r - 2:r + 3, c - 2:c + 3].any(), f"particle at pixel {p.round(1)} not drawn"
rows, cols = np.nonzero(white)
near = [np.min(np.hypot(pixels[:, 0] - (c + 0.5), pixels[:, 1] - (r + 0.5))) for r, c in zip(rows, cols)]
assert max(near) <= 2.5, f"a white pixel {max(near):.1f} px from every particle"
print(f"particles: {len(visible)} of 24 in sight, each drawn where its position projects ({white.sum()} px)")
status, image = browse(cloud_html, f"{flat}&frame=10&{camera}&particles=0", os.path.join(work, "no-particles.png"))
assert status["particles"] == 0 and not np.all(image == 255, axis=-1).any(), status

# Refusals: an existing page, too few frames, an ensemble's file, a file that is not a run.
p = subprocess.run([noether, "view", h5, "-o", html], capture_output=True, text=True)
assert p.returncode == 2 and "exists; noether does not overwrite output unless asked: pass --force" in p.stderr, p.stderr
p = subprocess.run([noether, "view", h5, "--max-frames", "1"], capture_output=True, text=True)
assert p.returncode == 2 and "--max-frames" in p.stderr, p.stderr
ens = os.path.join(work, "ens.h5")
p = subprocess.run([noether, "ensemble", os.path.join(src, "examples", "dumbbells.yaml"), "--vary",
                    "bodies.alpha.mass=list(1.5, 1.6)", "--samples", "2", "--set", "run.t_end=0.1", "-o", ens, "--force"],
                   capture_output=True, text=True)
assert p.returncode == 0, p.stderr
p = subprocess.run([noether, "view", ens], capture_output=True, text=True)
assert p.returncode == 2 and "no sample's run is beside it" in p.stderr and "--trajectories K" in p.stderr, p.stderr
scene = os.path.join(src, "examples", "dumbbells.yaml")
p = subprocess.run([noether, "view", scene, "-o", os.path.join(work, "x.html")], capture_output=True, text=True)
assert p.returncode == 2 and "not an HDF5 file" in p.stderr, p.stderr
assert not os.path.exists(os.path.join(work, "x.html"))
print("view: all checks passed")
