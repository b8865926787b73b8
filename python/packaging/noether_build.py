"""The build backend of `pip install .` (PEP 517; docs/python.md, "pip install").

noether is a CMake project: a driver, shared libraries, plugins and a Python module over them.
This backend builds it with CMake and packs the install tree into one wheel:

    noether/                        the Python package          -> site-packages/noether
    noether-V.data/data/bin/noether the driver                  -> <venv>/bin/noether
    noether-V.data/data/lib/...     libnoether*, the plugins    -> <venv>/lib/...
    noether-V.data/data/include/... headers and the CMake       -> <venv>/include, <venv>/lib/cmake
                                    package for out-of-tree plugins
    noether-V.data/data/share/...   the plot scripts            -> <venv>/share/noether

so the venv is an install prefix like any other (`cmake --install --prefix`): the driver finds
libnoether through its RUNPATH ($ORIGIN/../lib), the Python module through its own
($ORIGIN/../../.. from <prefix>/lib/python3.X/site-packages/noether), and both find the bundled
plugins next to libnoether (<prefix>/lib/noether/plugins). `pip uninstall noether` removes every
file the wheel's RECORD lists.

Why a backend of its own: it needs nothing but the standard library, so `build-system.requires`
is empty and pip's build isolation installs nothing — `pip install .` works offline, without
`--no-build-isolation`, with only the Debian packages tools/install-deps.sh installs. (A
setuptools backend would have pip fetch setuptools into the isolated environment.)

Options (`pip install . --config-settings KEY=VALUE`, or the environment):
  build-dir   CMake's build folder (default <source>/build/pip-<wheel tag>; kept, so a second
              `pip install .` rebuilds only what changed)
  jobs        parallel compile jobs (default CMAKE_BUILD_PARALLEL_LEVEL, else every CPU)
"""
import base64
import functools
import hashlib
import io
import os
import re
import shutil
import stat
import subprocess
import sys
import sysconfig
import tarfile
import tempfile
import zipfile
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[2]
NAME = "noether"
SUMMARY = "Bodies under mutual gravity: the full body problem and point masses"
# The Python module's dependency (Debian: python3-numpy). Reading output files (noether.read) needs
# h5py and plots matplotlib: extras, because Debian's python3-h5py registers itself as the
# distribution "h5py._debian_h5py_serial", so a required "h5py" would send pip to an index even
# where h5py imports; noether.read says so clearly when h5py is missing.
REQUIRES = ["numpy"]
LICENSE = "BSD-3-Clause"  # SPDX; the text: LICENSE (README.md, "Licence")
EXTRAS = {"output": ["h5py"], "plots": ["h5py", "matplotlib"]}
PYTHON_DIR = "lib/python3/dist-packages/noether"  # where CMake installs the package (python/CMakeLists.txt)


@functools.cache
def _version():
    text = (SOURCE / "CMakeLists.txt").read_text()
    m = re.search(r"project\(noether\s+VERSION\s+([0-9.]+)", text)
    if not m:
        raise RuntimeError(f"{SOURCE / 'CMakeLists.txt'}: no project(noether VERSION ...)")
    return m.group(1)


def _tag():
    """The wheel's compatibility tag: the interpreter that runs pip, since the extension module
    and the libraries are built for it and this machine."""
    if sys.implementation.name != "cpython":
        raise RuntimeError(f"noether's Python module is a CPython extension; {sys.executable} is "
                           f"{sys.implementation.name}")
    python = "cp%d%d" % sys.version_info[:2]
    platform = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    return f"{python}-{python}{sys.abiflags}-{platform}"


def _dist_info():
    return f"{NAME}-{_version()}.dist-info"


def _metadata():
    lines = ["Metadata-Version: 2.1", f"Name: {NAME}", f"Version: {_version()}", f"Summary: {SUMMARY}",
             f"License: {LICENSE}", "Classifier: License :: OSI Approved :: BSD License", "Requires-Python: >=3.9"]
    lines += [f"Requires-Dist: {r}" for r in REQUIRES]
    for extra, reqs in EXTRAS.items():
        lines.append(f"Provides-Extra: {extra}")
        lines += [f'Requires-Dist: {r}; extra == "{extra}"' for r in reqs]
    readme = SOURCE / "README.md"
    header = "\n".join(lines) + "\nDescription-Content-Type: text/markdown\n\n"
    return header + (readme.read_text() if readme.exists() else "")


def _wheel_file():
    return ("Wheel-Version: 1.0\n"
            f"Generator: noether_build ({NAME} {_version()})\n"
            "Root-Is-Purelib: false\n"
            f"Tag: {_tag()}\n")


def _option(config_settings, key, env=None):
    if config_settings and config_settings.get(key):
        return config_settings[key]
    return os.environ.get(env) if env else None


def _run(cmd, what):
    print("noether_build:", " ".join(str(c) for c in cmd), file=sys.stderr, flush=True)
    try:
        # The output goes to pip's stderr: shown with `pip install -v`, and by pip when it fails.
        subprocess.run([str(c) for c in cmd], check=True, stdout=sys.stderr, stderr=sys.stderr)
    except FileNotFoundError:
        raise RuntimeError(f"{what}: {cmd[0]} is not installed; ./tools/install-deps.sh installs "
                           "everything noether's build needs (Debian packages)") from None
    except subprocess.CalledProcessError as e:
        raise RuntimeError(f"{what} failed (exit {e.returncode}); its output is above (pip install -v shows "
                           "it in full). Missing Debian packages? ./tools/install-deps.sh installs them") from None


def _build_and_install(config_settings, prefix):
    """Configures, builds and installs noether into `prefix` (a staging folder)."""
    build = Path(_option(config_settings, "build-dir") or SOURCE / "build" / f"pip-{_tag()}")
    configure = ["cmake", "-S", SOURCE, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                 "-DNOETHER_BUILD_TESTS=OFF", "-DNOETHER_BUILD_BENCHMARKS=OFF", "-DNOETHER_BUILD_PYTHON=ON",
                 "-DNOETHER_VERSIONED_LIBRARIES=OFF", "-DCMAKE_INSTALL_LIBDIR=lib",
                 # The module for the interpreter that installs it (a venv's python: its base's headers).
                 f"-DPython_EXECUTABLE={sys.executable}"]
    if not (build / "CMakeCache.txt").exists() and shutil.which("ninja"):
        configure += ["-G", "Ninja"]
    _run(configure, "configuring noether with CMake")
    jobs = _option(config_settings, "jobs", "CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
    _run(["cmake", "--build", build, "--parallel", jobs], "building noether")
    _run(["cmake", "--install", build, "--prefix", prefix], "installing noether into the wheel's staging folder")


def _wheel_entries(prefix):
    """(path in the wheel, file) for every file of the install tree."""
    data = f"{NAME}-{_version()}.data/data"
    entries = []
    for path in sorted(Path(prefix).rglob("*")):
        rel = path.relative_to(prefix).as_posix()
        if path.is_symlink():  # a wheel has no symlinks (NOETHER_VERSIONED_LIBRARIES=OFF makes none)
            raise RuntimeError(f"the install tree holds a symlink, which a wheel cannot: {rel}")
        if path.is_dir():
            continue
        if rel.startswith(PYTHON_DIR + "/"):
            entries.append((NAME + rel[len(PYTHON_DIR):], path))
        elif "/__pycache__/" not in rel:
            entries.append((f"{data}/{rel}", path))
    if not any(name == f"{NAME}/__init__.py" for name, _ in entries):
        raise RuntimeError(f"the install tree has no {PYTHON_DIR}/__init__.py: was the Python module built?")
    return entries


def _record_line(name, content):
    digest = base64.urlsafe_b64encode(hashlib.sha256(content).digest()).rstrip(b"=").decode()
    return f"{name},sha256={digest},{len(content)}"


def _add(zf, name, content, mode=0o644):
    info = zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0))
    info.compress_type = zipfile.ZIP_DEFLATED
    info.external_attr = (stat.S_IFREG | mode) << 16  # pip keeps the executable bit
    zf.writestr(info, content)


# ---- PEP 517 hooks ----

def get_requires_for_build_wheel(config_settings=None):
    return []


def get_requires_for_build_sdist(config_settings=None):
    return []


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    info = Path(metadata_directory) / _dist_info()
    info.mkdir(parents=True, exist_ok=True)
    (info / "METADATA").write_text(_metadata())
    (info / "WHEEL").write_text(_wheel_file())
    return info.name


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    wheel_name = f"{NAME}-{_version()}-{_tag()}.whl"
    with tempfile.TemporaryDirectory(prefix="noether-wheel-") as staging:
        _build_and_install(config_settings, staging)
        records = []
        target = Path(wheel_directory) / wheel_name
        with zipfile.ZipFile(target, "w") as zf:
            for name, path in _wheel_entries(staging):
                content = path.read_bytes()
                _add(zf, name, content, stat.S_IMODE(path.stat().st_mode))
                records.append(_record_line(name, content))
            for name, content in (("METADATA", _metadata()), ("WHEEL", _wheel_file()),
                                  ("LICENSE", (SOURCE / "LICENSE").read_text())):
                arcname = f"{_dist_info()}/{name}"
                _add(zf, arcname, content.encode())
                records.append(_record_line(arcname, content.encode()))
            records.append(f"{_dist_info()}/RECORD,,")
            _add(zf, f"{_dist_info()}/RECORD", ("\n".join(records) + "\n").encode())
    return wheel_name


def _source_files():
    """The files of the source distribution: git's tracked files in a clone, else every file
    but the build folders (an unpacked sdist)."""
    if (SOURCE / ".git").exists() and shutil.which("git"):
        out = subprocess.run(["git", "-C", str(SOURCE), "ls-files", "-z"], check=True, capture_output=True).stdout
        return [f for f in out.decode().split("\0") if f and (SOURCE / f).is_file()]
    return sorted(p.relative_to(SOURCE).as_posix() for p in SOURCE.rglob("*")
                  if p.is_file() and p.relative_to(SOURCE).parts[0] not in ("build", ".git")
                  and "__pycache__" not in p.parts)


def build_sdist(sdist_directory, config_settings=None):
    base = f"{NAME}-{_version()}"
    target = Path(sdist_directory) / f"{base}.tar.gz"
    with tarfile.open(target, "w:gz", format=tarfile.PAX_FORMAT) as tar:
        pkg_info = _metadata().encode()
        info = tarfile.TarInfo(f"{base}/PKG-INFO")
        info.size = len(pkg_info)
        tar.addfile(info, io.BytesIO(pkg_info))
        for rel in _source_files():
            tar.add(SOURCE / rel, arcname=f"{base}/{rel}", recursive=False)
    return target.name
