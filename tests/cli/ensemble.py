"""ensemble.py NOETHER SOURCE_DIR WORK_DIR [light]: `noether ensemble` (docs/ensembles.md); `light`
(the sanitizer build, ~10× slower) uses fewer and shorter samples.

  1. The same ensemble with 1 and 2 threads, and with `mpirun -n 2`, gives the same file, every
     dataset bitwise (the wall times under /timing excepted): samples draw from (seed, index)
     and land at their index.
  2. Killed with SIGKILL at random moments (5 times) and resumed each time, an ensemble ends
     equal to an uninterrupted one: no sample lost, none run twice (resume runs only the samples
     without an outcome).
  3. A sample whose integrator fails is recorded as failed with its message; the others run; exit 3.
  (and --trajectories K writes the first K samples' full output files; each sample records the
  mutual period and its error that `noether run` prints).
  4. Bad distributions and unknown keys are refused (exit 2) before any sample runs: no file.
  5. A damaged outcome (a flipped byte) is refused by sample, the file unchanged; an outcome
     whose checksum was never written (a kill between the two) runs again and ends identical.
"""
import os
import random
import signal
import subprocess
import sys
import time

import h5py
import numpy as np

noether, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
light = len(sys.argv) > 4 and sys.argv[4] == "light"
N = "32" if light else "128"           # samples
T_END = "run.t_end=1" if light else "run.t_end=4"
os.makedirs(work, exist_ok=True)
os.chdir(work)
for name in os.listdir("."):
    os.remove(name)
scene = os.path.join(src, "examples", "dumbbells.yaml")
failures = []
VARY = ["--vary", "bodies.alpha.angular_velocity.2=normal(9, 0.5)", "--vary", "bodies.beta.mass=uniform(2.9, 3.1)",
        "--vary", "bodies.alpha.position.2=grid(0.1, 0.3, 4)"]


def ensemble(out, *extra, check=True):
    p = subprocess.run([noether, "ensemble", scene, *VARY, "--set", T_END, "-o", out, *extra],
                       capture_output=True, text=True)
    if check and p.returncode != 0:
        failures.append(f"ensemble {out} {extra}: exit {p.returncode}: {p.stderr.strip()}")
    return p


def datasets(path):
    out = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda n, o: out.__setitem__(n, o[()]) if isinstance(o, h5py.Dataset)
                     and not n.startswith("timing") else None)
    return out


def same(a, b, what):
    A, B = datasets(a), datasets(b)
    if sorted(A) != sorted(B):
        failures.append(f"{what}: different datasets {sorted(set(A) ^ set(B))}")
        return
    for k in A:
        if A[k].tobytes() != B[k].tobytes():
            failures.append(f"{what}: /{k} differs")


# 1. Threads.
t = time.monotonic()
ensemble("one.h5", "--samples", N, "--threads", "1")
duration = time.monotonic() - t
ensemble("two.h5", "--samples", N, "--threads", "2")
same("one.h5", "two.h5", "1 vs 2 threads")
with h5py.File("one.h5") as f:
    if not (f["outcome"][()] == 0).all():
        failures.append(f"outcomes {f['outcome'][()]}")
    grid = f["inputs/bodies.alpha.position.2"][()]
    if not np.allclose(sorted(set(grid)), np.linspace(0.1, 0.3, 4), rtol=0, atol=1e-15):
        failures.append(f"the grid's values {sorted(set(grid))}")
    spin = f["inputs/bodies.alpha.angular_velocity.2"][()]
    if not (abs(spin.mean() - 9) < 4 * 0.5 / np.sqrt(len(spin)) and 0.3 < spin.std() < 0.7):  # normal(9, 0.5)
        failures.append(f"normal(9, 0.5) drew mean {spin.mean()}, sd {spin.std()}")
    if not (f["trustworthy"][()] == 1).all():
        failures.append(f"trustworthy {f['trustworthy'][()]}")
    if not np.isfinite(f["orbit/period"][()]).all():
        failures.append("the mutual orbit's period is missing")

# 1a. --trajectories K: the first K samples' full output files end where /final says.
p = subprocess.run([noether, "ensemble", scene, *VARY, "--set", T_END, "-o", "traj.h5", "--samples", "8",
                    "--trajectories", "2"], capture_output=True, text=True)
with h5py.File("traj.h5") as f:
    final = f["final/positions"][()]
for i in range(3):
    path = f"traj-sample-{i}.h5"
    if i < 2 and not os.path.exists(path):
        failures.append(f"--trajectories 2 wrote no {path}")
    elif i < 2:
        with h5py.File(path) as g:
            if g["particles/bodies/position/value"][-1].tobytes() != final[i].tobytes():
                failures.append(f"{path} does not end at /final/positions[{i}]")
    elif os.path.exists(path):
        failures.append(f"--trajectories 2 also wrote {path}")

# 1c. Samples that finish but cannot be trusted say so (a threshold no run meets).
p = subprocess.run([noether, "ensemble", scene, *VARY, "--set", T_END, "--set", "run.trust.energy=1e-15", "-o",
                    "untrusted.h5", "--samples", "4"], capture_output=True, text=True)
with h5py.File("untrusted.h5") as f:
    trust, outcome = f["trustworthy"][()], f["outcome"][()]
    message = [m.decode() for m in f["message"][()]]
if p.returncode != 0 or not (trust == 0).all() or not (outcome == 0).all() \
        or not all(m.startswith("untrustworthy: relative energy error") for m in message) \
        or "4 UNTRUSTWORTHY samples" not in p.stderr:
    failures.append(f"untrustworthy samples: exit {p.returncode}, trustworthy {trust}, {message[:1]}, {p.stderr!r}")

# 1d. Each sample records the mutual period its summary prints (from the trajectory, with its
# error), not only the osculating one: bit for bit `noether run`'s.
didymos = os.path.join(src, "examples", "didymos.yaml")
p = subprocess.run([noether, "ensemble", didymos, "--vary", "bodies.dimorphos.velocity.1=list(0.1741158386581219)",
                    "--samples", "1", "--set", "run.t_end=86400", "-o", "period.h5"], capture_output=True, text=True)
r = subprocess.run([noether, "run", didymos, "--set", "run.t_end=86400", "--summary", "json", "-o", "period-run.h5"],
                   capture_output=True, text=True)
if p.returncode != 0 or r.returncode != 0:
    failures.append(f"the period ensemble: exit {p.returncode}, {r.returncode}: {p.stderr[-300:]} {r.stderr[-300:]}")
else:
    import json
    summary = json.loads(r.stdout)
    with h5py.File("period.h5") as f:
        recorded = (f["summary/mutual_period"][0], f["summary/mutual_period_error"][0], f["orbit/period"][0])
    if recorded[:2] != (summary["mutual_period"], summary["mutual_period_error"]) or recorded[2] == recorded[0]:
        failures.append(f"the ensemble's mutual period {recorded} against the run's {summary['mutual_period']} "
                        f"± {summary['mutual_period_error']}")
    # and each body's rotation and libration periods, as its summary's spin states (eqs. 17.13, 17.14)
    spins = {s["body"]: s for s in summary["spin_states"]}
    with h5py.File("period.h5") as f:
        periods = {"didymos.spin_period": f["indicators/didymos.spin_period"][0],
                   "dimorphos.spin_period": f["indicators/dimorphos.spin_period"][0],
                   "dimorphos.libration_period": f["indicators/dimorphos.libration_period"][0]}
        unit = f["indicators/dimorphos.libration_period"].attrs["unit"]
        unit = unit.decode() if isinstance(unit, bytes) else unit
    expected = {"didymos.spin_period": spins["didymos"]["spin_period"],
                "dimorphos.spin_period": spins["dimorphos"]["spin_period"],
                "dimorphos.libration_period": spins["dimorphos"]["libration_period"]}
    if periods != expected or unit != "s" or not 8130 < periods["didymos.spin_period"] < 8140:
        failures.append(f"the ensemble's spin periods {periods} [{unit}] against the run's {expected}")

# 1b. Across processes: `mpirun -n 2` (oversubscribed where there are fewer cores) gives the same file.
mpirun = "/usr/bin/mpirun"
if os.path.exists(mpirun):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
    # Under the sanitizers, OpenMPI's own allocations left at MPI_Finalize are reported as leaks:
    # leak checking is off for the MPI runs (the other checks stay on).
    env["ASAN_OPTIONS"] = env.get("ASAN_OPTIONS", "") + ":detect_leaks=0"
    p = subprocess.run([mpirun, "-n", "2", noether, "ensemble", scene, *VARY, "--set", T_END, "-o", "mpi.h5",
                        "--samples", N], capture_output=True, text=True, env=env)
    if p.returncode != 0 or "and 1 more ranks" not in p.stdout:
        failures.append(f"mpirun -n 2: exit {p.returncode}: {p.stdout[-300:]} {p.stderr[-500:]}")
    else:
        same("one.h5", "mpi.h5", "1 thread vs mpirun -n 2")
    p = subprocess.run([mpirun, "-n", "2", noether, "ensemble", scene, "--vary", "bodies.beta.mass=gauss(1, 2)",
                        "--samples", "4", "-o", "mpi-refused.h5"], capture_output=True, text=True, env=env)
    if p.returncode != 2 or "unknown distribution 'gauss'" not in p.stderr or os.path.exists("mpi-refused.h5"):
        failures.append(f"mpirun with a bad --vary: exit {p.returncode}: {p.stderr[-300:]}")
else:
    failures.append("no /usr/bin/mpirun (openmpi-bin, installed by tools/install-deps.sh)")

# 2. Kill and resume: 5 kills at random moments, each continuation resumed; a run that ends
# before its kill starts the file afresh (the result must be the same whichever way it is made).
rng = random.Random(3)
kills, resumed_with_work = 0, 0
base = [noether, "ensemble", scene, *VARY, "--set", T_END, "-o", "killed.h5", "--samples", N,
        "--threads", "2"]
args = base + ["--force"]
def committed(path):
    """Samples with an outcome in a file being written (0 while it does not exist or opens)."""
    try:
        with h5py.File(path, "r", locking=False) as f:
            return int((f["outcome"][()] >= 0).sum())
    except (OSError, KeyError):
        return 0


while kills < 5:
    before = committed("killed.h5") if "--resume" in args else 0
    p = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    # Killed only after it committed something (on a loaded machine a kill at a random moment
    # may otherwise always come before the first commit), then at a random moment.
    deadline = time.monotonic() + 60
    while committed("killed.h5") <= before and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.005)
    time.sleep(rng.uniform(0.0, 0.1) * duration)
    if p.poll() is None:
        p.send_signal(signal.SIGKILL)
        kills += 1
    out = p.communicate()[0]
    if p.returncode == 0:  # finished first: again from nothing
        args = base + ["--force"]
        continue
    args = base + (["--resume"] if os.path.exists("killed.h5") else [])
p = subprocess.run(base + ["--resume"], capture_output=True, text=True)
if p.returncode != 0:
    failures.append(f"the last resume failed: {p.stderr.strip()}")
else:
    same("one.h5", "killed.h5", f"killed {kills} times and resumed")
    line = p.stdout.strip().split("\n")[1]
    print(line)
    if " 0 finished before" in line:
        failures.append("the last resume found no finished sample: the kills came before any commit")

# 3. A failing sample.
p = subprocess.run([noether, "ensemble", scene, "--vary", "integrator.max_steps=list(40, 0)", "--samples", "8",
                    "--set", "integrator={plugin: cvode, max_steps: 0}", "--set", "run.t_end=2", "-o", "fail.h5"],
                   capture_output=True, text=True)
with h5py.File("fail.h5") as f:
    outcome, steps = f["outcome"][()], f["inputs/integrator.max_steps"][()]
    trust = f["trustworthy"][()]
    message = [m.decode() for m in f["message"][()]]
if p.returncode != 3 or not ((outcome == 2) == (steps == 40)).all() or not (outcome == 0).any():
    failures.append(f"failing samples: exit {p.returncode}, outcomes {outcome}, max_steps {steps}")
if not ((trust == -1) == (outcome == 2)).all():
    failures.append(f"failed samples have no verdict: trustworthy {trust}, outcomes {outcome}")
if not all("max_steps" in m for m, o in zip(message, outcome) if o == 2):
    failures.append(f"failed samples' messages {message}")

# 4. Refused before any run.
for spec, expect in [("bodies.beta.mass=normal(1)", "normal takes \\(mean, sd\\)"),
                     ("bodies.beta.mass=gauss(1, 2)", "unknown distribution 'gauss'"),
                     ("bodies.beta.mass=uniform(2, 1)", "needs a < b"),
                     ("bodies.beta.mass=log-uniform(0, 1)", "needs 0 < a < b"),
                     ("bodies.beta.mass=grid(1, 2, 2.5)", "whole n"),
                     ("bodies.beta.mass=list(1, x)", "'x' is not a finite number"),
                     ("bodies.gamma.mass=uniform(1, 2)", "no 'gamma'"),
                     ("bodies.beta.mas=uniform(1, 2)", "mas"),
                     ("bodies.beta.mass", "expected KEY=DISTRIBUTION")]:
    p = subprocess.run([noether, "ensemble", scene, "--vary", spec, "--samples", "4", "-o", "refused.h5"],
                       capture_output=True, text=True)
    import re
    if p.returncode != 2 or not re.search(expect, p.stderr) or os.path.exists("refused.h5"):
        failures.append(f"--vary {spec}: exit {p.returncode}, {p.stderr.strip()!r}")
p = subprocess.run([noether, "ensemble", scene, "--vary", "bodies.beta.mass=uniform(1, 2)", "-o", "refused.h5"],
                   capture_output=True, text=True)
if p.returncode != 2 or "--samples N is needed" not in p.stderr:
    failures.append(f"no --samples: {p.returncode} {p.stderr!r}")
p = ensemble("one.h5", "--samples", N, check=False)
if p.returncode != 2 or "exists" not in p.stderr:
    failures.append(f"an existing file: {p.returncode} {p.stderr!r}")
p = ensemble("one.h5", "--samples", "24", "--resume", check=False)
if p.returncode != 2 or "holds another ensemble" not in p.stderr:
    failures.append(f"resuming another ensemble: {p.returncode} {p.stderr!r}")

# 5. Damaged outcomes: refused by sample (exit 2, the file unchanged), or run again.
import shutil
shutil.copy("one.h5", "damaged.h5")
with h5py.File("damaged.h5", "r+") as f:
    o = f["outcome"][()]
    o[5] = 1 - o[5] if o[5] in (0, 1) else 0
    f["outcome"][5] = o[5]
before = open("damaged.h5", "rb").read()
p = ensemble("damaged.h5", "--samples", N, "--resume", check=False)
if p.returncode != 2 or "the outcome of sample 5 does not match its checksum" not in p.stderr:
    failures.append(f"a damaged outcome: exit {p.returncode}, {p.stderr.strip()!r}")
if open("damaged.h5", "rb").read() != before:
    failures.append("a refused ensemble file was changed")
shutil.copy("one.h5", "uncommitted.h5")
with h5py.File("uncommitted.h5", "r+") as f:
    f["outcome_checksum"][7] = 0
p = ensemble("uncommitted.h5", "--samples", N, "--resume")
if p.returncode == 0:
    same("one.h5", "uncommitted.h5", "an uncommitted outcome run again")
    if "(1 run here," not in p.stdout:
        failures.append(f"an uncommitted outcome: not run again alone: {p.stdout.strip()!r}")

for f in failures:
    print("FAIL:", f)
print(f"ensemble: {len(failures)} failures; kills {kills}")
sys.exit(1 if failures else 0)
