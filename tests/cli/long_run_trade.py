"""long_run_trade.py NOETHER SOURCE_DIR WORK_DIR: tools/long_run_trade.py measures what it says on
the bound dumbbells at T = 20 and 200: the LGVI's energy error stays bounded (grows < 2x over 10x
the time) while dopri5's drifts (grows > 5x at the same tolerance), and every run it reports
finished with the evaluations and wall time of its `noether run`."""
import json
import os
import subprocess
import sys

noether, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
out = os.path.join(work, "trade.json")
p = subprocess.run(["/usr/bin/python3", f"{src}/tools/long_run_trade.py", f"{src}/examples/dumbbells-bound.yaml",
                    "--t-end", "20,200", "--noether", noether, "--budget", "60", "--json", out],
                   capture_output=True, text=True, check=True)
print(p.stdout)
with open(out) as f:
    r = json.load(f)
short, long = r["20.0"], r["200.0"]
for name in short:
    assert "failed" not in short[name] and "failed" not in long[name], (name, short[name], long[name])
    assert long[name]["evals"] > 5 * short[name]["evals"], name
lgvi = long["lgvi"]["energy"] / short["lgvi"]["energy"]
dopri = long["dopri5 rtol 1e-08"]["energy"] / short["dopri5 rtol 1e-08"]["energy"]
assert lgvi < 2.0, f"LGVI energy error grew {lgvi:.2f}x over 10x the time"
assert dopri > 5.0, f"dopri5 energy error grew only {dopri:.2f}x over 10x the time"
assert "equal max|dE|" in p.stdout
print(f"energy error growth over T = 20 -> 200: lgvi {lgvi:.2f}x, dopri5 rtol 1e-8 {dopri:.2f}x")
