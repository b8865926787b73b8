"""Reading noether's HDF5 output (docs/user-guide.md, "Output"): named arrays with their units."""
import sys

import numpy as np

from . import _noether

# Short names for the series of an output file: name → path, from the table the writer uses
# (noether.output_series(); docs/user-guide.md, "Output").
SERIES = {s["name"]: s["path"].lstrip("/") for s in _noether.output_series()}


class Output:
    """An output file of `noether run` (or of a Simulation with output=...), read whole.

    out["positions"] is an array [frame][body][xyz]; out.unit("positions") its unit ("km", "L",
    …); out.description(name) what it is; out.names the bodies; out.frames the number of complete
    frames (a killed run's file holds only those: the rest is cut off). Names: see SERIES, or
    out.keys(). out.outcome is "completed", "stopped: …", "failed: …", or None for a killed run.
    out.particles: the scene's massless particles' arrays (fate, time, body, position, …; empty
    without particles).
    """

    def __init__(self, path):
        self.path = str(path)
        self._arrays, self._units, self._descriptions = {}, {}, {}
        try:
            import h5py
        except ImportError:
            raise _noether.OutputError(
                f"reading {self.path} needs h5py, which {sys.executable} does not have: noether's Python pieces are "
                "for Debian's /usr/bin/python3 (tools/install-deps.sh installs python3-h5py; README, \"Python\")") from None
        try:
            f = h5py.File(self.path, "r", locking=False)
        except FileNotFoundError:
            raise _noether.OutputError(f"{self.path}: no such file") from None
        except OSError as e:  # not HDF5, damaged, unreadable
            raise _noether.OutputError(f"{self.path} is not an HDF5 file noether can read ({e})") from None
        with f:
            if "frames_complete" not in f or "parameters" not in f:
                raise _noether.OutputError(f"{self.path} is not an output file of noether (no /frames_complete)")
            self.frames = int(f["frames_complete"][()])
            self.names = [n.decode() if isinstance(n, bytes) else n for n in f["particles/bodies/name"][()]]
            self.masses = f["particles/bodies/mass"][()]
            self.parameters = dict(f["parameters"].attrs)
            self.scene = _text(f["parameters/scene"][()])
            self.outcome = f["work"].attrs["outcome"] if "work" in f else None
            self.work = dict(f["work"].attrs) if "work" in f else {}
            for name, path in SERIES.items():
                if path in f:
                    d = f[path]
                    self._arrays[name] = d[: self.frames]
                    self._units[name] = d.attrs.get("unit", "")
                    self._descriptions[name] = d.attrs.get("description", "")
            # The massless particles (docs/user-guide.md, "Particles"): fate, time, body, position, …
            self.particles = {}
            if "test_particles" in f:
                for name, d in f["test_particles"].items():
                    self.particles[name] = [_text(v) for v in d[()]] if name in ("fields", "surfaces") else d[()]
            if "particles/bodies/inertia" in f:
                self.inertias = f["particles/bodies/inertia"][()]
            # Each solid body's shape in its body frame: {"kind": "ellipsoid", "semi_axes": [a, b, c]}
            # or {"kind": "polyhedron", "vertices": [n][3], "faces": [m][3]}.
            self.shapes = {}
            for name, g in (f["parameters/shapes"].items() if "parameters/shapes" in f else []):
                shape = {"kind": _text(g.attrs["kind"]), "description": _text(g.attrs["description"])}
                if "semi_axes" in g.attrs:
                    shape["semi_axes"] = g.attrs["semi_axes"]
                if "vertices" in g:
                    shape["vertices"], shape["faces"] = g["vertices"][()], g["faces"][()]
                self.shapes[name] = shape

    def keys(self):
        return list(self._arrays)

    def __getitem__(self, name):
        if name not in self._arrays:
            raise KeyError(f"{name!r}: this file has {', '.join(self._arrays)}")
        return self._arrays[name]

    def __contains__(self, name):
        return name in self._arrays

    def unit(self, name):
        self[name]
        return self._units[name]

    def description(self, name):
        self[name]
        return self._descriptions[name]

    def energy_error(self):
        """E − E0 at every frame."""
        E = self["energy"]
        return E - E[0]

    def __repr__(self):
        return f"<noether.Output {self.path}: {self.frames} frames, bodies {self.names}, {self.outcome or 'killed'}>"


def read(path):
    """The output file at `path` as an Output."""
    return Output(path)


def _text(value):
    if isinstance(value, bytes):
        return value.decode()
    if isinstance(value, np.ndarray):
        return value.tobytes().decode()
    return str(value)
