"""noether.view: the page `noether view` writes, from Python and inline in Jupyter
(docs/visualisation.md, "In Python and Jupyter")."""
import html
import re
import subprocess

import pytest

import noether
from conftest import NOETHER


@pytest.fixture
def dumbbell_run(dumbbells, tmp_path):
    dumbbells["run"] = {"t_end": 2, "output_every": 0.01}
    path = tmp_path / "dumbbells.h5"
    sim = noether.Simulation(dumbbells, output=path)
    sim.integrate(2)
    sim.finish()
    return path


def test_the_page_is_the_drivers(dumbbell_run, tmp_path):
    v = noether.view(dumbbell_run, params="view=frame:beta&axes=1")
    assert (v.frames_in_file, v.frames_shown, v.notes) == (201, 201, [])
    page = tmp_path / "cli.html"
    p = subprocess.run([NOETHER, "view", str(dumbbell_run), "-o", str(page), "--params", "view=frame:beta&axes=1"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert v.html == page.read_text(encoding="utf-8")
    assert '"params":"view=frame:beta&axes=1"' in v.html
    # The same from a noether.Output, and decimated as asked.
    w = noether.view(noether.read(dumbbell_run), max_frames=11, title="two dumbbells")
    assert (w.frames_shown, w.notes) == (11, ["decimated: 11 of the file's 201 frames, evenly spaced (--max-frames)"])
    assert '"title":"two dumbbells"' in w.html
    assert re.fullmatch(r"<noether.View: 11 of 201 frames, \d\.\d MB>", repr(w)), repr(w)


def test_jupyter_shows_the_page_in_an_iframe(dumbbell_run, tmp_path):
    v = noether.view(dumbbell_run, height=400)
    shown = v._repr_html_()
    m = re.fullmatch(r'<iframe srcdoc="([^"]*)" sandbox="allow-scripts" style="width: 100%; height: 400px; border: 0" '
                     r'title="noether view"></iframe>', shown, re.S)
    assert m, shown[:300]
    assert html.unescape(m.group(1)) == v.html
    saved = v.save(tmp_path / "v.html")
    assert open(saved, encoding="utf-8").read() == v.html
    with pytest.raises(noether.OutputError, match="exists; force=True replaces it"):
        v.save(tmp_path / "v.html")
    v.save(tmp_path / "v.html", force=True)


def test_what_cannot_be_viewed_is_refused(dumbbell_run, dumbbells, source):
    with pytest.raises(noether.SceneError, match="parameter 'colour' is not one the page knows"):
        noether.view(dumbbell_run, params="frame=3&colour=red")
    with pytest.raises(noether.SceneError, match="view=frame:gamma: give inertial, barycentric"):
        noether.view(dumbbell_run, params="view=frame:gamma")
    with pytest.raises(noether.SceneError, match="at least 2 frames"):
        noether.view(dumbbell_run, max_frames=1)
    with pytest.raises(noether.OutputError, match="not an HDF5 file"):
        noether.view(source / "examples" / "dumbbells.yaml")
    with pytest.raises(TypeError, match="viewed through its output file"):
        noether.view(noether.Simulation(dumbbells))


def test_a_point_mass_has_no_body_frame(source, tmp_path):
    path = tmp_path / "eight.h5"
    sim = noether.Simulation(source / "examples" / "figure-eight.yaml", output=path, set=["run.t_end=0.632591398"])
    sim.integrate(0.632591398)
    sim.finish()
    with pytest.raises(noether.SceneError, match="is a point mass, which has no body frame; centre:"):
        noether.view(path, params="view=frame:" + sim.names[0])
    assert noether.view(path, params="view=centre:" + sim.names[0]).frames_shown == sim.summary()["output_frames"]


def test_several_runs_in_one_page(dumbbell_run, dumbbells, tmp_path):
    dumbbells["run"] = {"t_end": 1, "output_every": 0.01}  # the same frame times, ending at half
    dumbbells["bodies"][0]["angular_velocity"] = [0, 0, 5]
    other = tmp_path / "slower.h5"
    sim = noether.Simulation(dumbbells, output=other)
    sim.integrate(1)
    sim.finish()
    v = noether.view([dumbbell_run, noether.read(other)])
    assert v.frames_shown == 201 and v.notes == ["slower.h5 ends at t = 1 (101 frames): not drawn after it"]
    assert '"title":"dumbbells.h5 and 1 more"' in v.html and '"others":[{"label":"slower.h5","frames":101,' in v.html
    page = tmp_path / "both.html"
    p = subprocess.run([NOETHER, "view", str(dumbbell_run), str(other), "-o", str(page)], capture_output=True, text=True)
    assert p.returncode == 0 and "(201 of 201 frames, 2 runs," in p.stdout, p.stdout + p.stderr
    assert v.html == page.read_text(encoding="utf-8")
    with pytest.raises(noether.SceneError, match="--samples picks an ensemble's sample runs"):
        noether.view(dumbbell_run, samples=[0])
