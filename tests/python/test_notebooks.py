"""examples/notebooks/: every notebook executed top to bottom in a fresh kernel (nbclient, from
Debian's python3-nbclient and python3-ipykernel), so that they cannot rot. Each notebook checks
its own physics with assertions (a period against the two-body or spin-orbit prediction, a
bounded energy error); a failed assertion, or any error, fails this test with the cell."""
import os
import pathlib

import nbclient
import nbformat
import pytest

from conftest import SOURCE

NOTEBOOKS = sorted((SOURCE / "examples" / "notebooks").glob("*.ipynb"))


def test_there_are_notebooks():
    assert len(NOTEBOOKS) >= 3


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_runs_and_its_checks_hold(path, monkeypatch):
    notebook = nbformat.read(path, as_version=4)
    code = "\n".join(c.source for c in notebook.cells if c.cell_type == "code")
    assert "assert " in code, f"{path.name} checks nothing"
    # Committed without outputs: the notebook is its source, not a record of a run.
    for cell in notebook.cells:
        if cell.cell_type == "code":
            assert not cell.outputs and cell.execution_count is None, f"{path.name} was committed with outputs"
    # The kernel starts in the notebook's folder: the module's path must not be relative.
    paths = [str(pathlib.Path(p).resolve()) for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(paths))
    monkeypatch.setenv("NOETHER_SOURCE_DIR", str(SOURCE))
    monkeypatch.setenv("PYDEVD_DISABLE_FILE_VALIDATION", "1")  # ipykernel's debugger notice on stderr
    monkeypatch.setenv("MPLBACKEND", "Agg")
    client = nbclient.NotebookClient(notebook, timeout=600, kernel_name="python3",
                                     resources={"metadata": {"path": str(path.parent)}})
    try:
        client.execute()
    except nbclient.exceptions.CellExecutionError as e:
        pytest.fail(f"{path.name}: {e}", pytrace=False)
