"""noether.view: a run in 3-D, inline in Jupyter or saved as a page (docs/visualisation.md)."""
import html as _html
import os

from . import _noether
from .output import Output


class View:
    """The page `noether view` writes for a run: `view.html` (text), `view.save(path)`; shown
    inline by Jupyter (an <iframe> holding the page, `height` pixels high)."""

    def __init__(self, html, frames_in_file, frames_shown, notes, height):
        self.html = html
        self.frames_in_file, self.frames_shown, self.notes = frames_in_file, frames_shown, list(notes)
        self.height = int(height)

    def _repr_html_(self):
        # The page as the iframe's own document (srcdoc): no file, no server; scripts only, in a
        # sandbox of its own. It carries three.js (0.85 MB) in the notebook.
        return (f'<iframe srcdoc="{_html.escape(self.html, quote=True)}" sandbox="allow-scripts" '
                f'style="width: 100%; height: {self.height}px; border: 0" title="noether view"></iframe>')

    def save(self, path, force=False):
        """Writes the page (refused when `path` exists, unless force)."""
        path = os.fspath(path)
        if os.path.exists(path) and not force:
            raise _noether.OutputError(f"{path} exists; force=True replaces it")
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.html)
        return path

    def __repr__(self):
        return f"<noether.View: {self.frames_shown} of {self.frames_in_file} frames, {len(self.html) / 1e6:.1f} MB>"


def view(run, max_frames=5000, title=None, params="", height=520, samples=None):
    """`noether view` in Python: the bodies of a run's output file (a path or a noether.Output)
    in 3-D — shapes, attitudes, trails, a time slider — as a View that Jupyter shows inline.
    run may also be a list of runs of the same bodies and frame times (the first drawn opaque, the
    others translucent), or an ensemble's file, whose samples' runs (`noether ensemble
    --trajectories K`) it shows: `samples` picks them (default: those there are, at most 8).
    max_frames: at most that many frames, evenly spaced by index (the first and last among
    them); title: the page's (default: the file's name); params: the page's parameters, e.g.
    "view=frame:alpha&axes=1" (docs/visualisation.md, "Parameters"). A Simulation is viewed
    through its output file once it has finished."""
    def path_of(r):
        if isinstance(r, Output):
            return r.path
        if isinstance(r, (str, os.PathLike)):
            return os.fspath(r)
        raise TypeError("noether.view(run): the path of a run's output file, or a noether.Output (or a list of them); "
                        "a Simulation is viewed through its output file: Simulation(..., output='run.h5'), "
                        "sim.finish(), noether.view('run.h5')")
    paths = [path_of(r) for r in run] if isinstance(run, (list, tuple)) else [path_of(run)]
    page, frames_in_file, frames_shown, notes = _noether.view_html(paths, int(max_frames), title or "", params,
                                                                   [int(s) for s in (samples or [])])
    return View(page.decode("utf-8"), frames_in_file, frames_shown, notes, height)
