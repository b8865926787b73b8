"""host_layering.py: host's folders keep the contracts docs/architecture.md gives them.

    host_layering.py SOURCE_DIR

docs/architecture.md, "host's folders", has one table row per folder of host/src: the folder and,
in its last column, what its files may include of the other folders — a folder (`io/`) or one
header (`run/event_watch.hpp`); none named: no other folder. This reads that table and every
`#include "..."` under host/src, and fails, naming the file and the line, on an include the row
does not allow, an include that is not a path from host/src, a folder the table lacks, or a row
naming a folder that does not exist; and on an HDF5 identifier closed by hand (`H5Fclose(`, …)
anywhere but io/h5.hpp, the one HDF5 layer, whose H5Handle closes them."""
import os
import re
import sys

source = sys.argv[1]
doc = open(os.path.join(source, "docs", "architecture.md"), encoding="utf-8").read()
section = doc.split("### host's folders", 1)
if len(section) != 2:
    sys.exit("host_layering: docs/architecture.md has no section \"host's folders\"")
contracts = {}
for line in section[1].splitlines():
    if line.startswith("## "):
        break
    cells = [c.strip() for c in line.strip().strip("|").split("|")] if line.startswith("|") else []
    m = re.fullmatch(r"`(\w+)/`", cells[0]) if cells else None
    if m:
        contracts[m.group(1)] = re.findall(r"`([\w/.]+)`", cells[-1])

src = os.path.join(source, "host", "src")
folders = sorted(d for d in os.listdir(src) if os.path.isdir(os.path.join(src, d)))
failures = []
for d in folders:
    if d not in contracts:
        failures.append(f"host/src/{d}/: no row in docs/architecture.md's table of host's folders")
for d in contracts:
    if d not in folders:
        failures.append(f"docs/architecture.md names host/src/{d}/, which does not exist")
include = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
closed_by_hand = re.compile(r"\bH5[A-Z]close\s*\(|\bH5Idec_ref\s*\(")
checked = 0
for d in folders:
    for root, _, files in os.walk(os.path.join(src, d)):
        for f in sorted(files):
            if not f.endswith((".cpp", ".hpp")):
                continue
            path = os.path.join(root, f)
            rel = os.path.relpath(path, source)
            for n, line in enumerate(open(path, encoding="utf-8"), 1):
                if closed_by_hand.search(line) and rel != os.path.join("host", "src", "io", "h5.hpp"):
                    failures.append(f"{rel}:{n}: an HDF5 identifier closed by hand: hold it in an io::H5Handle "
                                    "(io/h5.hpp, the one HDF5 layer)")
                m = include.match(line)
                if not m:
                    continue
                target = m.group(1)
                checked += 1
                if not os.path.isfile(os.path.join(src, target)):
                    failures.append(f"{rel}:{n}: #include \"{target}\" is not a path from host/src")
                    continue
                folder = target.split("/", 1)[0]
                allowed = contracts.get(d, [])
                if folder != d and f"{folder}/" not in allowed and target not in allowed:
                    failures.append(f"{rel}:{n}: {d}/ may not include {target} (docs/architecture.md, "
                                    f"\"host's folders\": {d}/ may include {', '.join(allowed) or 'no other folder'})")
for f in failures:
    print("FAIL", f)
print(f"host_layering: {len(folders)} folders, {checked} includes checked, {len(failures)} failures")
sys.exit(1 if failures else 0)
