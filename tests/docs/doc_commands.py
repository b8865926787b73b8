"""doc_commands.py: every command README.md and docs/*.md show is run by a test.

    doc_commands.py list SOURCE_DIR                 print the commands found, one per line
    doc_commands.py run SOURCE_DIR NOETHER          run them, in the order the docs show them

A command is a line of an indented or ```sh code block, or an inline `code` span, that starts
with `noether` (or a path to it) and names no placeholder (SCENE, FILE, [options], ...); a
backslash continues it. Each one is
  - run here, from a scratch folder that sees the repository's examples/ and tests/ (so outputs
    such as -o dumbbells.h5 or --plot docs/img/x.png land in the scratch folder) and, as
    ../shared/data, the archived data beside the clone (a command that reads it is skipped, saying
    so, where it is absent), and must exit with status 0 — or the status the doc states next to
    it ("exits 2"); or
  - listed in COVERED_ELSEWHERE with the test that runs it (commands that build or install).
A command that is neither fails the test, so docs cannot show a command nothing runs.
When the lines after a command in the same block show its output ("label   value" lines, as
the summary prints them), every such line must appear in the actual output with the same
numbers, wall times excepted.
`python3 examples/...py` commands and every ```python block run with Debian's python3 and the
build tree's module (PYTHONPATH); a doc's ```python blocks run in order as one script, which must
exit 0 (its asserts are the doc's claims)."""
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time

PLACEHOLDER = re.compile(r"(^|\s)[A-Z][A-Z0-9_]*(\.\w+)?(=\S*)?(\s|$)|\b[A-Z]\b|\.\.\.|…")  # SCENE, OUT.h5, KEY=VALUE, F
STARTS = re.compile(r"^(\./build/release/bin/noether|noether|\$HOME/noether/bin/noether|tools/\w+\.py|python3 examples/\S+\.py)\s")

# Commands that are not run here, with the test that runs them.
OUT_OF_TREE = "tests/install/out_of_tree.sh runs this workflow (label install)"
PIP = "tests/install/pip_install.sh runs this workflow (install.pip-install, label slow)"
COVERED_ELSEWHERE = {
    "./tools/test.sh": "the test command itself (.ci/run)",
    "cmake --install build/release --prefix /opt/noether": OUT_OF_TREE,
    "./tools/install-deps.sh": "called by ./tools/test.sh, which CI runs",
    "cmake --preset release && cmake --build --preset release": "./tools/test.sh",
    "cmake --install build/release --prefix $HOME/noether": OUT_OF_TREE,
    "cmake -S examples/custom-potential -B build-j2 -DCMAKE_PREFIX_PATH=$HOME/noether": OUT_OF_TREE,
    "cmake --build build-j2": OUT_OF_TREE,
    "export NOETHER_PLUGIN_PATH=$PWD/build-j2": OUT_OF_TREE,
    "$HOME/noether/bin/noether plugins": OUT_OF_TREE,
    "$HOME/noether/bin/noether check-potential examples/custom-potential/j2-orbit.yaml": OUT_OF_TREE + " (j2.check-potential)",
    "$HOME/noether/bin/noether run examples/custom-potential/j2-orbit.yaml -o j2.h5": OUT_OF_TREE + " (j2.run)",
    "examples/custom-potential/check_precession.py j2.h5": OUT_OF_TREE + " (j2.nodal-precession)",
    "ctest --test-dir build-j2": OUT_OF_TREE,
    "python3 -m venv --system-site-packages v && v/bin/pip install .": PIP,
    "v/bin/noether run examples/dumbbells.yaml": PIP,
    'v/bin/python -c "import noether"': PIP,
    "v/bin/pip uninstall -y noether": PIP,
    "noether run examples/didymos-ejecta-cloud.yaml -o ejecta-cloud.h5 --threads 2":
        "tests/cli/ejecta_cloud.py runs the cloud's first 300 particles (the 10^4 take 2 min on CI's 2 cores)",
    "tools/plot_ejecta.py ejecta-cloud.h5 docs/img/ejecta-cloud.png":
        "tests/cli/ejecta_cloud.py draws the 300 particles' run and checks its counts",
    "mpirun -n 8 noether ensemble examples/didymos.yaml --vary 'bodies.dimorphos.velocity.1=normal(0.1714158386581219, 0.0001)' --samples 10000 -o dart.h5":
        "tests/cli/ensemble.py runs an ensemble under mpirun -n 2 (8 ranks and 10^4 samples do not fit a 2-core CI)",
}
# ./tools/demo.sh: its build step must name existing targets, and its run (the noether line of
# tools/demo.sh) is run here with README's "The demo prints" block as its output.
DEMO = "./tools/demo.sh"


def next_block(lines, j):
    """The lines of the first indented block at or after line j, unindented."""
    while j < len(lines) and not lines[j].startswith("    "):
        j += 1
    block = []
    while j < len(lines) and lines[j].startswith("    "):
        block.append(lines[j][4:])
        j += 1
    return block


def python_blocks(path):
    """(first line, the text of every ```python block of a Markdown file, joined in order)."""
    lines = open(path, encoding="utf-8").read().split("\n")
    code, first, inside = [], None, False
    for i, line in enumerate(lines):
        if line.startswith("```"):
            inside = not inside and line[3:].strip() == "python"
            if inside and first is None:
                first = i + 1
            continue
        if inside:
            code.append(line)
    return first, "\n".join(code)


def blocks(path):
    """(line number, text, following output lines) of every command in a Markdown file."""
    lines = open(path, encoding="utf-8").read().split("\n")
    found = []
    in_fence = False
    fence_is_shell = False
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("```"):
            in_fence = not in_fence
            fence_is_shell = in_fence and line[3:].strip() in ("sh", "bash", "console")
            i += 1
            continue
        code = None
        if in_fence and fence_is_shell:
            if line.strip() and not line.strip().startswith("#"):
                found.append((i + 1, line.split("  #")[0].strip(), []))
            i += 1
            continue
        elif not in_fence and line.startswith("    ") and (i == 0 or lines[i - 1].strip() == "" or lines[i - 1].startswith("    ")):
            code = line[4:]
        if code is not None:
            text = code.split("  #")[0].rstrip()
            start = i
            while text.endswith("\\") and i + 1 < len(lines):
                i += 1
                nxt = lines[i][4:] if lines[i].startswith("    ") else lines[i]
                text = text[:-1].rstrip() + " " + nxt.split("  #")[0].strip()
            if STARTS.match(text.strip()) or text.strip() in COVERED_ELSEWHERE or text.strip().startswith("./tools/"):
                output = []
                j = i + 1
                while j < len(lines) and lines[j].startswith("    ") and not STARTS.match(lines[j][4:]):
                    output.append(lines[j][4:])
                    j += 1
                if not output and text.strip() == DEMO:  # README: "The demo prints" and a block
                    j = i + 1
                    while j < len(lines) and "The demo prints" not in lines[j]:
                        j += 1
                    output = next_block(lines, j)
                found.append((start + 1, text.strip(), output))
        elif not in_fence:
            for span in re.findall(r"`([^`]+)`", line):
                # an inline command names a file (a bare `noether run` is the command's name)
                if STARTS.match(span + " ") and len(span.split()) > 1 and (span.startswith("tools/") or re.search(r"/|\.ya?ml\b", span.split(None, 1)[1])):
                    # after "Command:", its output is the next indented block
                    output = next_block(lines, i + 1) if line.startswith("Command:") else []
                    found.append((i + 1, span.strip(), output))
        i += 1
    return found


def commands(src):
    files = [os.path.join(src, "README.md")] + sorted(
        os.path.join(src, "docs", f) for f in os.listdir(os.path.join(src, "docs")) if f.endswith(".md"))
    out = []
    for f in files:
        for line, text, output in blocks(f):
            args = " ".join(text.split()[1:])
            unquoted = re.sub(r"'[^']*'", "''", args)  # [ outside quotes is an optional part
            if STARTS.match(text) and (PLACEHOLDER.search(args) or "[" in unquoted):
                continue  # a synopsis, not a command
            out.append((os.path.relpath(f, src), line, text, output))
    return out


def main():
    mode, src = sys.argv[1], os.path.abspath(sys.argv[2])
    found = commands(src)
    if mode == "list":
        for f, line, text, _ in found:
            print(f"{f}:{line}: {text}")
        return 0
    noether = os.path.abspath(sys.argv[3])
    failures = []
    scratch_dir = tempfile.TemporaryDirectory(prefix="noether-docs-")
    # The scratch folder sits one level down, beside a link to the archived data that lies beside
    # the clone (../shared), so `../shared/data/...` in a doc's command means what it does there.
    scratch = os.path.join(scratch_dir.name, "work")
    os.makedirs(scratch)
    shared = os.path.join(src, os.pardir, "shared")
    has_shared = os.path.isdir(os.path.join(shared, "data"))
    if has_shared:
        os.symlink(os.path.abspath(shared), os.path.join(scratch_dir.name, "shared"))
    for name in ("examples", "tests"):
        os.symlink(os.path.join(src, name), os.path.join(scratch, name))
    os.makedirs(os.path.join(scratch, "docs", "img"))
    module = os.path.join(os.path.dirname(noether), os.pardir, "lib", "python3", "dist-packages")
    python_env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=os.path.abspath(module))
    docs = [os.path.join(src, "README.md")] + sorted(
        os.path.join(src, "docs", f) for f in os.listdir(os.path.join(src, "docs")) if f.endswith(".md"))
    for path in docs:  # the ```python blocks of each doc, as one script
        first, code = python_blocks(path)
        if first is None:
            continue
        where = f"{os.path.relpath(path, src)}:{first}"
        t0 = time.time()
        proc = subprocess.run(["/usr/bin/python3", "-c", code], cwd=scratch, capture_output=True, text=True,
                              env=python_env)
        print(f"{where}: the doc's python blocks  → exit {proc.returncode} in {time.time() - t0:.1f} s", flush=True)
        if proc.returncode != 0:
            failures.append(f"{where}: the doc's python blocks exited {proc.returncode}: {proc.stderr.strip()[-600:]}")
    for f, line, text, output in found:
        where = f"{f}:{line}"
        if text in COVERED_ELSEWHERE:
            continue
        if text == DEMO:
            demo = open(os.path.join(src, "tools", "demo.sh")).read()
            build = re.search(r"^cmake --build --preset release --target (.*)$", demo, re.M)
            if build:
                for target in build.group(1).split():
                    proc = subprocess.run(["cmake", "--build", os.path.join(src, "build", "release"), "--target", target],
                                          capture_output=True, text=True)
                    if proc.returncode != 0:
                        failures.append(f"{where}: tools/demo.sh builds target '{target}', which fails: {proc.stdout[-300:]}")
            text = re.search(r"^(\./build/release/bin/noether .*?)(\s+#.*)?$", demo, re.M).group(1)
        elif not STARTS.match(text):
            failures.append(f"{where}: `{text}` is neither run by this test nor listed in COVERED_ELSEWHERE")
            continue
        if "../shared/data" in text and not has_shared:
            print(f"{where}: {text}  → skipped: ../shared/data is absent beside the clone", flush=True)
            continue
        argv = shlex.split(text)
        if argv[0].startswith("tools/"):  # the repository's scripts, with Debian's python3
            argv = ["/usr/bin/python3", os.path.join(src, argv[0])] + argv[1:]
        elif argv[0] == "python3":  # the examples, with the build tree's module
            argv = ["/usr/bin/python3", os.path.join(src, argv[1])] + argv[2:]
        else:
            argv[0] = noether
        t0 = time.time()
        proc = subprocess.run(argv, cwd=scratch, capture_output=True, text=True, env=python_env)
        print(f"{where}: {text}  → exit {proc.returncode} in {time.time() - t0:.1f} s", flush=True)
        if proc.returncode != 0:
            failures.append(f"{where}: `{text}` exited {proc.returncode}: {proc.stderr.strip()[-400:]}")
            continue
        actual = set()
        for got in proc.stdout.split("\n"):
            m = re.match(r"^(\S.*?\S)\s{2,}(\S.*)$", got)
            if m:
                actual.add((m.group(1), m.group(2).strip()))
        labels = {label for label, _ in actual}
        for shown in output:
            m = re.match(r"^(\S.*?\S)\s{2,}(\S.*)$", shown)
            if not m or m.group(1) in ("wall time",) or "..." in shown or "…" in shown:
                continue
            label, value = m.group(1), m.group(2).strip()
            if label not in labels:
                failures.append(f"{where}: the doc shows '{label}', which the output does not print")
            elif (label, value) not in actual:
                printed = [v for l, v in actual if l == label]
                failures.append(f"{where}: the doc shows '{label}  {value}', the output {printed}")
    for f in failures:
        print("FAIL " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
