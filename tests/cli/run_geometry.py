"""run_geometry.py: a run's bodies as its HDF5 file gives them, for the tests of pictures of runs
(view.py, export.py): positions, exact attitudes (/checkpoint/attitude), shapes (/parameters/shapes;
a dumbbell's spheres as docs/visualisation.md draws them)."""
import os
import re
import subprocess

import h5py
import numpy as np


def ellipsoid_mesh(axes, m=96, k=48):
    """An ellipsoid of semi-axes `axes` as a latitude-longitude mesh: (vertices [n][3], faces [m][3])."""
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, m, endpoint=False), np.linspace(0, np.pi, k + 1))
    p = np.stack([np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v)], -1) * axes
    vertices = p.reshape(-1, 3)
    faces = []
    for i in range(k):
        for j in range(m):
            a, b = i * m + j, i * m + (j + 1) % m
            faces += [[a, b, a + m], [b, b + m, a + m]]
    return vertices, np.array(faces)


class Run:
    """names, mass [body], t [frame], x [frame][body][3], R {body: [frame][3][3]} (rigid bodies),
    meshes {body: (vertices, faces)} in the body frame and kinds {body: "ellipsoid" | "polyhedron"
    | "dumbbell"}, semi_axes {body: [3]}, dumbbell {body: length}."""

    def __init__(self, h5):
        with h5py.File(h5, "r") as f:
            self.names = [n.decode() if isinstance(n, bytes) else n for n in f["particles/bodies/name"][:]]
            self.mass = f["particles/bodies/mass"][:]
            self.x = f["particles/bodies/position/value"][:]
            self.t = f["particles/bodies/position/time"][:]
            self.R = {}
            if "checkpoint/attitude" in f:
                rigid_to_body = f["particles/bodies/orientation"].attrs["body_index"]
                R = f["checkpoint/attitude"][:]
                for k, j in enumerate(rigid_to_body):
                    self.R[int(j)] = R[:, k]
            self.meshes, self.kinds, self.semi_axes, self.dumbbell = {}, {}, {}, {}
            for j, name in enumerate(self.names):
                g = f.get(f"parameters/shapes/{name}")
                if g is None:
                    continue
                self.kinds[j] = g.attrs["kind"]
                if self.kinds[j] == "ellipsoid":
                    self.semi_axes[j] = g.attrs["semi_axes"]
                    self.meshes[j] = ellipsoid_mesh(g.attrs["semi_axes"])
                else:
                    self.meshes[j] = (g["vertices"][:], g["faces"][:])
            # A dumbbell of length L: its two points drawn as spheres of radius L/10 (a fifth of the
            # cluster's extent, docs/visualisation.md).
            scene = f["parameters/scene_as_run"][()].decode()
            for name, length in re.findall(r"- name: (\S+)(?:(?!- name:)[\s\S])*?dumbbell:\s*\n\s*length: (\S+)", scene):
                L = float(length)
                v, faces = ellipsoid_mesh(np.full(3, L / 10))
                self.meshes[self.names.index(name)] = (np.vstack([v + [L / 2, 0, 0], v - [L / 2, 0, 0]]),
                                                       np.vstack([faces, faces + len(v)]))
                self.kinds[self.names.index(name)] = "dumbbell"
                self.dumbbell[self.names.index(name)] = L

    def origin(self, k, view):
        """The origin of a frame to watch from (viewer.js's frameOfView) at file frame k."""
        if view == "barycentric":
            return self.mass @ self.x[k] / self.mass.sum()
        if view.startswith("centre:") or view.startswith("frame:"):
            return self.x[k, self.names.index(view.split(":", 1)[1])]
        return np.zeros(3)


def run_scene(noether, src, work, scene, name, *sets):
    """Runs examples/SCENE with --set overrides into WORK/NAME.h5; returns its path."""
    out = os.path.join(work, name + ".h5")
    args = [noether, "run", os.path.join(src, "examples", scene), "-o", out, "--force"]
    for s in sets:
        args += ["--set", s]
    p = subprocess.run(args, capture_output=True, text=True)
    assert p.returncode == 0, f"{scene}: exit {p.returncode}\n{p.stderr}"
    return out
