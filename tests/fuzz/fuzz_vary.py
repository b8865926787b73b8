#!/usr/bin/python3
"""Fuzz `noether ensemble --vary`: random and malformed keys, distributions and sample counts on
the LGVI paper's dumbbells (a few hundred steps a sample).

    fuzz_vary.py NOETHER SOURCE_DIR WORK_DIR [CASES] [SEED]

Every case must end in one of:
  - refused: exit 2 with a "noether:" message, and no ensemble file (nor a hidden one) left;
  - ran: exit 0 (every sample finished) or 3 (some failed), and the file holds every sample's
    row: an outcome of 0, 1 or 2, a message for each failure, and inputs that are what the
    distribution can give (uniform and log-uniform within [a, b], grid values on the grid, list
    values from the list, normal values finite).
Anything else is a finding (a crash, a hang, another exit code, a file left by a refusal, a row
not written, a value outside its distribution). Prints counts and exits 1 on any finding.
(docs/reliability.md, "Fuzzing".)
"""
import math
import pathlib
import random
import resource
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import h5py
import numpy as np

TIME_LIMIT = 60
MEMORY_LIMIT = 3 << 30

KEYS = ["G", "bodies.alpha.mass", "bodies.beta.mass", "bodies.alpha.position.0", "bodies.beta.velocity.1",
        "bodies.alpha.angular_velocity.2", "bodies.0.mass", "bodies.1.inertia.0", "integrator.step", "run.t_end"]
BAD_KEYS = ["bodies.gamma.mass", "bodies.alpha.nosuch", "bodies.alpha.position.7", "bodies.alpha.position.-1",
            "integrator.plugin", "bodies.alpha.name", "", ".", "G.", "..", "bodies", "bodies.2.mass",
            "run", "x" * 300, "bodies.alpha.mass.0", "bodies.α.mass", "potential.order", "bodies.alpha.shape"]
NOMINAL = {"G": 0.2222, "bodies.alpha.mass": 1.5, "bodies.beta.mass": 3.0, "bodies.alpha.position.0": 0.67,
           "bodies.beta.velocity.1": -0.33, "bodies.alpha.angular_velocity.2": 9.0, "bodies.0.mass": 1.5,
           "bodies.1.inertia.0": 0.003, "integrator.step": 0.0002, "run.t_end": 0.04}
SPECIAL = ["nan", "inf", "-inf", "1e308", "-1e308", "1e-308", "0", "-0", "", "x", "1e999", "0x10", "1,2",
           " 1 ", "1e", "--1", "+1", "1_000"]


def number(rng, nominal):
    r = rng.random()
    if r < 0.9:
        return repr(nominal * rng.uniform(0.5, 1.5))
    if r < 0.93:
        return repr(-abs(nominal))
    return rng.choice(SPECIAL)


def distribution(rng, key):
    nominal = NOMINAL.get(key, 1.0)
    kind = rng.choice(["normal", "uniform", "log-uniform", "list", "grid"] * 3 + ["other"])
    if kind == "normal":
        args = [number(rng, nominal), number(rng, nominal * 0.01)]
    elif kind in ("uniform", "log-uniform"):
        a, b = sorted([nominal * rng.uniform(0.8, 1.2), nominal * rng.uniform(0.8, 1.2)])
        args = [repr(a), repr(b)] if rng.random() < 0.7 else [number(rng, nominal), number(rng, nominal)]
    elif kind == "list":
        args = [number(rng, nominal) for _ in range(rng.choice([0, 1, 2, 3, 5]))]
    elif kind == "grid":
        args = [repr(nominal * 0.9), repr(nominal * 1.1), rng.choice(["1", "2", "3", "2", "3", "0", "-1", "2.5", "1e9", "1e10", "x"])]
        if rng.random() < 0.3:
            args[rng.randrange(2)] = number(rng, nominal)
    else:
        kind = rng.choice(["gauss", "normal", "uniform", "", "list", "NORMAL", "grid"])
        args = [number(rng, nominal) for _ in range(rng.choice([0, 1, 4]))]
    text = f"{kind}({', '.join(args)})"
    r = rng.random()
    if r < 0.05:
        text = text[:-1]                       # no closing parenthesis
    elif r < 0.08:
        text = text + ")"
    elif r < 0.10:
        text = text.replace("(", "((", 1)
    elif r < 0.12:
        text = text + " junk"
    return kind, args, text


def spec(rng):
    key = rng.choice(KEYS) if rng.random() < 0.9 else rng.choice(BAD_KEYS)
    kind, args, text = distribution(rng, key)
    r = rng.random()
    if r < 0.03:
        return key, None, key + text            # no '='
    if r < 0.05:
        return key, None, key + "==" + text
    return key, (kind, args), f"{key}={text}"


def within(kind, args, values):
    """Are the values ones the distribution can give? None if so, else why not."""
    args = [x.strip() for x in ",".join(args).split(",")] if args else []  # as noether splits them
    try:
        a = [float.fromhex(x) if "0x" in x.lower() else float(x) for x in args]  # C's strtod reads hex
    except ValueError:
        return "accepted arguments that are not numbers: %s" % args
    v = np.asarray(values, dtype=float)
    if not np.all(np.isfinite(v)):
        return "a value that is not finite"
    if kind in ("uniform", "log-uniform") and not np.all((v >= a[0]) & (v <= a[1])):
        return f"a value outside [{a[0]}, {a[1]}]: {v.min()} … {v.max()}"
    if kind == "log-uniform" and not np.all(v > 0):
        return "a non-positive log-uniform value"
    if kind == "list" and not all(any(x == y for y in a) for x in v):
        return f"a value not in the list {a}"
    if kind == "grid":
        n = int(a[2])
        grid = [a[0]] if n == 1 else [a[0] + (a[1] - a[0]) * k / (n - 1) for k in range(n)]
        if not all(any(abs(x - g) <= 1e-12 * max(1.0, abs(g)) for g in grid) for x in v):
            return f"a value off the grid {grid}"
    return None


def limit_resources():
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))


def run_case(noether, scene, work, k, rng):
    varies = [spec(rng) for _ in range(rng.choice([1, 1, 2, 3]))]
    if rng.random() < 0.05 and varies:
        varies.append(varies[0])               # the same key twice
    samples = rng.choice([None, 1, 2, 3, 4, 6, 6, 12, 0, 10 ** 15])
    out = work / f"ens-{k:04d}.h5"
    cmd = [noether, "ensemble", str(scene), "--set", "run.t_end=0.04", "--threads", "1", "-o", str(out)]
    for _, _, text in varies:
        cmd += ["--vary", text]
    if samples is not None:
        cmd += ["--samples", str(samples)]
    what = " ".join(cmd[2:])
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, errors="replace", timeout=TIME_LIMIT,
                           preexec_fn=limit_resources)
    except subprocess.TimeoutExpired:
        return "hang", what, f"more than {TIME_LIMIT} s"
    left = sorted(x.name for x in work.glob(f"*ens-{k:04d}.h5*"))
    if p.returncode < 0:
        return "crash", what, f"signal {-p.returncode}: {p.stderr[-400:]}"
    if p.returncode == 2:
        if not any(l.startswith("noether: ") for l in p.stderr.splitlines()):
            return "refused", what, f"exit 2 without a message: {p.stderr[-300:]}"
        if left:
            return "refused", what, f"files left by a refusal: {left}"
        return "refused", what, None
    if p.returncode not in (0, 3):
        return f"exit {p.returncode}", what, p.stderr[-400:]
    try:
        with h5py.File(out, "r") as f:
            outcome = f["outcome"][:]
            if np.any(outcome < 0) or np.any(outcome > 2):
                return "ran", what, f"outcomes not written: {outcome}"
            if (p.returncode == 3) != bool(np.any(outcome == 2)):
                return "ran", what, f"exit {p.returncode} but outcomes {outcome}"
            messages = f["message"][:]
            if any(o == 2 and not m for o, m in zip(outcome, messages)):
                return "ran", what, "a failed sample without a message"
            for key, parsed, text in varies:
                if parsed is None:
                    return "ran", what, f"accepted a --vary without '=': {text}"
                kind, args = parsed
                why = within(kind, args, f["inputs"][key][:])
                if why:
                    return "ran", what, f"--vary {text}: {why}"
    except (OSError, KeyError) as e:
        return "ran", what, f"the file does not read: {e}"
    finally:
        out.unlink(missing_ok=True)
    return "ran", what, None


def main():
    noether, source, work = sys.argv[1], pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
    cases = int(sys.argv[4]) if len(sys.argv) > 4 else 300
    seed = int(sys.argv[5]) if len(sys.argv) > 5 else 1
    work.mkdir(parents=True, exist_ok=True)
    scene = source / "examples" / "dumbbells.yaml"
    rngs = [random.Random(seed * 1_000_003 + k) for k in range(cases)]
    counts, findings = {}, []
    with ThreadPoolExecutor(max_workers=2) as pool:
        for outcome, what, finding in pool.map(lambda k: run_case(noether, scene, work, k, rngs[k]), range(cases)):
            counts[outcome] = counts.get(outcome, 0) + 1
            if finding:
                findings.append(f"{what}: {finding}")
    print(f"fuzz_vary: {cases} ensembles (seed {seed}): " + ", ".join(f"{n} {k}" for k, n in sorted(counts.items())))
    for f in findings:
        print("FINDING:", f)
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
