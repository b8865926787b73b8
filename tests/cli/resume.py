"""resume.py NOETHER SOURCE_DIR WORK_DIR [KILLS [T_END]]: a run killed with SIGKILL at random moments and
continued each time with `noether run --resume` ends with a file equal, bit for bit, to the one an
uninterrupted run writes (docs/user-guide.md, "Continuing a run").

For the LGVI (inertial Hamiltonian, and relative Lagrangian: a method whose variables are not the
State, restored from /checkpoint/integrator; the forced LGVI with tides, whose balance is read
back; with massless particles, restored from /checkpoint/particles; and everything at once — the
STM, sensitivities and the chaos indicators, an impulse, tides and particles, read back from their
frames, /checkpoint/run_features and /checkpoint/particles) and for rk4 on the dumbbells: one
uninterrupted run; then the same run started and killed at a random moment, resumed and killed
again, KILLS times (at least 5; at least 10 for everything at once), then resumed to the end. Asserted:
  * every frame is in the file exactly once: the times are the uninterrupted run's, in order (an
    impulse's two frames, before and after it, share its time in both);
  * the positions, exact momenta and attitudes, angular momenta, energies and step counts of every
    frame are bitwise the uninterrupted run's;
  * the final summary (max |E - E0| over the whole run, momentum errors, steps) is the same;
  * /checkpoint/resumed lists the continuations (those that got as far as opening the file).
"""
import json
import os
import random
import signal
import subprocess
import sys
import time

import h5py
import numpy as np

noether, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
kills = max(5, int(sys.argv[4]) if len(sys.argv) > 4 else 6)
t_end = sys.argv[5] if len(sys.argv) > 5 else "300"  # shorter under the sanitizers (10× slower)
os.makedirs(work, exist_ok=True)
os.chdir(work)
scene = os.path.join(src, "examples", "dumbbells.yaml")
random.seed(20261122)
failures = []

COMPARED = ["particles/bodies/position/time", "particles/bodies/position/value", "particles/bodies/position/step",
            "particles/bodies/velocity/value", "particles/bodies/orientation/value",
            "particles/bodies/angular_momentum/value", "checkpoint/linear_momentum", "checkpoint/attitude",
            "observables/energy/value", "observables/potential_energy/value",
            "observables/angular_momentum/value"]
SUMMARY_KEYS = ["E0", "max_abs_energy_error", "max_rel_linear_momentum_error", "max_rel_angular_momentum_error",
                "max_orthogonality_error", "closest_approach", "output_frames", "final_time", "steps"]


def frames_complete(path):
    """The complete frames of a file being written (0 while it does not exist or opens)."""
    try:
        with h5py.File(path, "r", locking=False) as f:
            return int(f["frames_complete"][()])
    except (OSError, KeyError):
        return 0


def summary_of(stdout):
    return json.loads(stdout)


for label, overrides in [("lgvi", []), ("rk4", ["integrator={plugin: rk, method: rk4, step: 0.0002}"]),
                         ("lgvi-relative-lagrangian",
                          ["integrator={plugin: lgvi, step: 0.0002, frame: relative, form: lagrangian}"]),
                         # a force beyond the potential: its balance (W, ΔP, ΔL) is read back with every
                         # frame, and the forced LGVI's opening kick starts from it
                         ("lgvi-tides", ["forces=[{plugin: tides, body: beta, k2: 0.3, time_lag: 0.0001, radius: 0.25}]"]),
                         # massless particles: where they stand is read back from the checkpoint the
                         # last complete block wrote (/checkpoint/particles), their recorded positions
                         # with every frame, their fates at the end
                         ("lgvi-particles", ["particles={states: [[3, 0, 0, 0, 0.577, 0], [0.67, 0, 1.2, 0, 0.67, -0.5]], "
                                             "check: 1}"]),
                         # everything a run carries at once, killed at least 10 times: the STM and
                         # sensitivities (to an initial velocity, to a mass whose stencil the
                         # continuation makes again, to the impulse's Δv) read back from their
                         # frames; the chaos indicators and the count of applied impulses from
                         # /checkpoint/run_features; an impulse; tides; particles. A tenth of the
                         # time (each step carries 32 tangent columns).
                         ("lgvi-all", ["run.stm=true", "run.chaos=true",
                                       f"impulses=[{{body: beta, time: {float(t_end) / 20!r}, delta_v: [0, 0.002, 0]}}]",
                                       "run.sensitivities=[bodies.beta.velocity, bodies.alpha.mass, impulses.0.delta_v.1]",
                                       "forces=[{plugin: tides, body: beta, k2: 0.3, time_lag: 0.0001, radius: 0.25}]",
                                       "particles={states: [[3, 0, 0, 0, 0.577, 0], [0.67, 0, 1.2, 0, 0.67, -0.5]], "
                                       "check: 1}",
                                       f"run.t_end={float(t_end) / 10!r}", "run.output_every=0.1"])]:
    sets = ["--set", f"run.t_end={t_end}", "--set", "run.output_every=0.01"]
    for o in overrides:
        sets += ["--set", o]
    full, part = f"{label}-full.h5", f"{label}-part.h5"
    for name in (full, part):
        if os.path.exists(name):
            os.remove(name)
    t = time.monotonic()
    done = subprocess.run([noether, "run", scene, "-o", full, "--no-progress", "--summary", "json"] + sets,
                          check=True, capture_output=True, text=True)
    duration = time.monotonic() - t
    reference = summary_of(done.stdout)

    # Killed KILLS times: the first run, then each continuation, at a random moment.
    command = [noether, "run", scene, "-o", part, "--no-progress"] + sets
    killed = resumed = 0
    case_kills = max(kills, 10) if label == "lgvi-all" else kills
    while killed < case_kills:
        fresh = "--resume" not in command
        p = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        # A fresh run is killed only once its file holds a complete frame (on a loaded machine
        # starting can take longer than the whole run's share a kill waits).
        deadline = time.monotonic() + 60
        while fresh and frames_complete(part) == 0 and p.poll() is None and time.monotonic() < deadline:
            time.sleep(0.005)
        # Each kill lands within the first eighth of a whole run's time (a continuation has less
        # to do than the whole run), so KILLS of them leave work for the last continuation.
        time.sleep(random.uniform(0.02, 0.12) * duration)
        if p.poll() is None:
            p.send_signal(signal.SIGKILL)
            killed += 1
        err = p.communicate()[1]
        if p.returncode not in (0, -signal.SIGKILL):
            # The first run was killed before its first block of frames: nothing to continue.
            if "no complete frame" in err:
                command = [noether, "run", scene, "-o", part, "--no-progress", "--force"] + sets
                continue
            failures.append(f"{label}: a continuation failed (exit {p.returncode}): {err.strip()}")
            break
        if p.returncode == 0:
            failures.append(f"{label}: a run finished before its kill ({killed} kills so far); the test needs "
                            "a longer run")
            break
        command = [noether, "run", "--resume", part, "--no-progress"]
        resumed += 1
    # To the end (afresh if the last kill came before the file had a complete frame).
    last = subprocess.run(command + ["--summary", "json"], capture_output=True, text=True)
    if last.returncode != 0 and ("no complete frame" in last.stderr or "no such file" in last.stderr):
        last = subprocess.run([noether, "run", scene, "-o", part, "--no-progress", "--force", "--summary", "json"]
                              + sets, capture_output=True, text=True)
        failures.append(f"{label}: the last kill left nothing to continue; the test needs later kills")
    if last.returncode != 0:
        failures.append(f"{label}: the last continuation failed: {last.stderr.strip()}")
        continue
    resumed += 1
    got = summary_of(last.stdout)

    with h5py.File(full, "r", locking=False) as a, h5py.File(part, "r", locking=False) as b:
        ta, tb = a["particles/bodies/position/time"][()], b["particles/bodies/position/time"][()]
        if int(b["frames_complete"][()]) != len(ta) or len(tb) != len(ta):
            failures.append(f"{label}: {len(tb)} frames (frames_complete {int(b['frames_complete'][()])}), "
                            f"the uninterrupted run has {len(ta)}")
        elif not np.array_equal(np.diff(tb) > 0, np.diff(ta) > 0):  # an impulse's two frames share its time
            failures.append(f"{label}: the times do not increase as the uninterrupted run's: a frame is missing or "
                            "repeated")
        extra = ["observables/force_balance/value"] if "observables/force_balance" in a else []
        if "derivatives" in a:
            extra += [f"derivatives/{k}/value" for k in ("stm", "sensitivity", "megno", "fli")] + ["checkpoint/run_features"]
        if "test_particles" in a:
            extra += ["particles/test_particles/position/value"] + [
                "test_particles/" + k for k in ("position", "velocity", "fate", "time", "body", "impact_point")]
        for key in COMPARED + extra:
            x, y = a[key][()], b[key][()]
            if x.shape != y.shape or x.tobytes() != y.tobytes():
                bad = np.argwhere((x != y).reshape(len(x), -1).any(axis=1)).ravel() if x.shape == y.shape else []
                failures.append(f"{label}: {key} differs from the uninterrupted run"
                                + (f" at {len(bad)} frames, first {bad[0]} (t = {ta[bad[0]]})" if len(bad) else
                                   f" (shapes {x.shape}, {y.shape})"))
        steps_a, steps_b = a["checkpoint/work"][:, 0], b["checkpoint/work"][:, 0]
        if not np.array_equal(steps_a, steps_b):
            failures.append(f"{label}: /checkpoint/work's step counts differ")
        resumes = b["checkpoint"].attrs.get("resumed", "").splitlines()
        # A continuation killed while it still read the file never opened it for writing.
        if not 1 <= len(resumes) <= resumed:
            failures.append(f"{label}: /checkpoint/resumed lists {len(resumes)} continuations, {resumed} were started")
        if b["work"].attrs["outcome"] != "completed":
            failures.append(f"{label}: the outcome is {b['work'].attrs['outcome']!r}")
    for key in (SUMMARY_KEYS + (["forces"] if "forces" in reference else []) + (["chaos"] if "chaos" in reference else [])
                + (["impulses", "impulse_energy"] if reference.get("impulses") else [])):
        if got[key] != reference[key]:
            failures.append(f"{label}: summary {key} = {got[key]!r}, uninterrupted {reference[key]!r}")
    print(f"{label}: killed {killed} times, resumed {resumed} times; {len(ta)} frames; "
          f"max|dE| {got['max_abs_energy_error']:.10e} (uninterrupted {reference['max_abs_energy_error']:.10e})")

for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
