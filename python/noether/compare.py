"""noether.compare: one scene under several integrators or models against a reference — the work
against precision of `noether compare`, as a table."""
import json
import os

import numpy as np

from . import _noether

# The numeric columns come from the run summary's schema (docs/user-guide.md, "Summary reference").
COLUMNS = ["family", "label", "ok", "error"] + list(_noether.compare_columns())


class Table:
    """The rows of a comparison. table["final_position_error"] is a column as a NumPy array,
    iterating gives the rows as dicts, str(table) is the table `noether compare` prints;
    reference, reference_error and reference_seconds describe the reference solution."""

    def __init__(self, result):
        self.rows = result["rows"]
        self.reference = result["reference"]
        self.reference_error = result["reference_error"]
        self.reference_error_note = result["reference_error_note"]
        self.reference_seconds = result["reference_seconds"]
        self._text = result["text"]

    columns = COLUMNS

    def __getitem__(self, column):
        if column not in COLUMNS:
            raise KeyError(f"{column!r}: columns are {', '.join(COLUMNS)}")
        values = [r[column] for r in self.rows]
        return np.array(values) if values and not isinstance(values[0], str) else values

    def __iter__(self):
        return iter(self.rows)

    def __len__(self):
        return len(self.rows)

    def __str__(self):
        return self._text

    __repr__ = __str__


def compare(scene, runs=(), models=(), set=(), reference_model=None, spec=None, repeats=1, max_wall_time=0.0):
    """Runs `scene` (a path or a dict) under each integrator of `runs` (dicts or YAML mappings;
    list values expand, as for `noether compare --run`) or each potential of `models`, and
    measures each against a reference (the default sweep and reference when neither is given).
    Returns a Table. repeats: runs per setting for the median wall time."""
    if isinstance(scene, dict):
        text, name = json.dumps(scene), "<dict>"
    else:
        name = os.fspath(scene)
        with open(name) as f:
            text = f.read()
    as_yaml = [json.dumps(r) if isinstance(r, dict) else str(r) for r in runs]
    model_yaml = [json.dumps(m) if isinstance(m, dict) else str(m) for m in models]
    ref = json.dumps(reference_model) if isinstance(reference_model, dict) else (reference_model or "")
    overrides = [set] if isinstance(set, str) else list(set)
    return Table(_noether.compare(text, name, overrides, as_yaml, model_yaml, ref, os.fspath(spec) if spec else "",
                                  int(repeats), float(max_wall_time)))
