"""The licence (README.md, "Licence"): LICENSE is the BSD 3-Clause text, and README.md,
CITATION.cff, pyproject.toml and the wheel's metadata (python/packaging/noether_build.py) all
name it, with the same SPDX identifier."""
import importlib.util
import re

SPDX = "BSD-3-Clause"


def test_licence_is_the_bsd_3_clause_text(source):
    text = (source / "LICENSE").read_text()
    assert text.startswith("BSD 3-Clause License\n")
    # its three conditions and the disclaimer, as the SPDX text has them
    for clause in ("1. Redistributions of source code must retain the above copyright notice",
                   "2. Redistributions in binary form must reproduce the above copyright notice",
                   "3. Neither the name of the copyright holder nor the names of its",
                   'THIS SOFTWARE IS PROVIDED BY THE COPYRIGHT HOLDERS AND CONTRIBUTORS "AS IS"'):
        assert clause in text, clause
    assert re.search(r"^Copyright \(c\) \d{4}, The noether developers$", text, re.M)


def test_every_place_that_says_the_licence_says_the_same(source):
    readme = (source / "README.md").read_text()
    section = readme[readme.index("## Licence"):]
    assert "[LICENSE](LICENSE)" in section and f"`{SPDX}`" in section
    assert "examples/shapes/NOTICE" in section  # the shape files keep their own terms
    assert re.search(rf"^license: {SPDX}$", (source / "CITATION.cff").read_text(), re.M)
    assert f"Licence: {SPDX} (LICENSE)" in (source / "pyproject.toml").read_text()
    spec = importlib.util.spec_from_file_location("noether_build", source / "python/packaging/noether_build.py")
    backend = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(backend)
    metadata = backend._metadata()
    assert f"\nLicense: {SPDX}\n" in metadata
    assert "\nClassifier: License :: OSI Approved :: BSD License\n" in metadata
