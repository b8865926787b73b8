"""summary_json.py NOETHER SOURCE_DIR: `noether run --summary json` prints one JSON object with
the text summary's numbers: README's --set example is untrustworthy with the relative energy
error of the text summary, the central-field Kepler scene has no linear momentum (null), and a
tolerance-driven scene lists its pair models."""
import json
import re
import subprocess
import sys

noether, src = sys.argv[1], sys.argv[2]


def run(*args):
    scene = [noether, "run", *args, "--no-progress"]
    js = json.loads(subprocess.run(scene + ["--summary", "json"], capture_output=True, text=True, check=True).stdout)
    text = subprocess.run(scene, capture_output=True, text=True, check=True).stdout
    return js, text


js, text = run(f"{src}/examples/dumbbells.yaml", "--set", "bodies.alpha.mass=2",
               "--set", "bodies.0.angular_velocity=[0, 0, 5]")
assert js["verdict"]["trustworthy"] is False, js["verdict"]
rel = float(re.search(r"relative to \|E0\|: ([0-9.e+-]+)", text).group(1))
assert abs(js["max_rel_energy_error"] - rel) <= 0.01 * rel, (js["max_rel_energy_error"], rel)
assert js["steps"] == 100000 and js["output_frames"] == 2001, js
assert js["stop_reason"] is None

js, _ = run(f"{src}/examples/kepler-jm.yaml", "--set", "run.t_end=10")
assert js["max_rel_linear_momentum_error"] is None and js["closest_approach"] is None, js
assert js["max_rel_angular_momentum_error"] is not None

js, _ = run(f"{src}/examples/kw4-ellipsoids.yaml", "--set",
            "potential={plugin: mutual-series, tolerance: 1.0e-6}", "--set", "run.t_end=3600")
assert len(js["pair_models"]) == 1 and js["pair_models"][0]["order"] > 0, js["pair_models"]
print("summary_json: untrustworthy verdict, null momenta and pair models as in the text summary")
