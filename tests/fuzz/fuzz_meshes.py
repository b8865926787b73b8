#!/usr/bin/python3
"""Fuzz noether's shape files: mutated OBJ files and CSV pairs, and a few huge ones, each run as
a body of a scene (`noether run`), with a memory limit and a time limit.

    fuzz_meshes.py NOETHER SOURCE_DIR WORK_DIR [CASES] [SEED]

Every case must end in one of:
  - accepted: exit 0, and the mesh is one an independent check (here, in Python) finds closed,
    consistently oriented and of positive volume; the summary's numbers finite;
  - a failed run: exit 3 with a message (the mesh was valid; the dynamics were not);
  - refused: exit 2 with one line "noether: SCENE:LINE: body 'rock': ..." that names the shape
    file (and, for a malformed line, its line number).
Anything else is a finding: another exit code, a signal (a crash), more than the time limit (a
hang), more than the memory limit, a refusal without the file's name, an accepted mesh that is
not a closed outward surface. Prints counts per outcome and exits 1 on any finding.
(docs/reliability.md, "Fuzzing": counts and outcomes of the recorded rounds.)
"""
import json
import os
import pathlib
import random
import re
import resource
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

MEMORY_LIMIT = 3 << 30   # bytes of address space per run
TIME_LIMIT = 60          # seconds per run

SCENE = """G: 6.674e-11
bodies:
  - name: rock
    density: 2500
    shape: {{polyhedron: {{{shape}, units: m}}}}
    position: [0, 0, 0]
    angular_velocity: [0, 0, 1e-4]
  - {{name: probe, mass: 1, position: [{probe}, 0, 0], velocity: [0, {speed}, 0]}}
potential: {{plugin: mutual-series, order: 2}}
integrator: {{plugin: lgvi, step: 1}}
run: {{t_end: 2, output_every: 1}}
"""

SPECIALS = ["nan", "inf", "-inf", "1e308", "-1e308", "1e-320", "0", "-0", "", "abc", "1e", "0x1p3",
            "99999999999999999999", "-1", "2147483648", "-2147483649", "1/2/3", "1//", "ÿ", "\x00", "1,5"]


def read_obj(path):
    v, f = [], []
    for line in pathlib.Path(path).read_text().splitlines():
        t = line.split()
        if t and t[0] == "v":
            v.append([float(x) if "x" not in x.lower() else float.fromhex(x) for x in t[1:4]])
        elif t and t[0] == "f":  # 1-based; negative: relative to the vertices so far
            f.append([i if i > 0 else i + len(v) + 1 for i in (int(x.split("/")[0]) for x in t[1:])])
    return v, f


def write_obj(v, f):
    return "".join(f"v {a!r} {b!r} {c!r}\n" for a, b, c in v) + "".join(
        "f " + " ".join(str(i) for i in face) + "\n" for face in f)


def icosphere(level, radius=50.0):
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
         (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    norm = lambda p: tuple(x / sum(y * y for y in p) ** 0.5 for x in p)
    v = [norm(p) for p in v]
    for _ in range(level):
        mid, g = {}, []

        def m(a, b):
            k = (min(a, b), max(a, b))
            if k not in mid:
                v.append(norm(tuple(x + y for x, y in zip(v[a], v[b]))))
                mid[k] = len(v) - 1
            return mid[k]
        for a, b, c in f:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            g += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = g
    return [[radius * x for x in p] for p in v], [[i + 1 for i in face] for face in f]


def independent_check(v, f):
    """Closed, every edge traversed once each way, positive volume (no self-intersection test)."""
    directed = set()
    for face in f:
        if len(face) != 3 or len(set(face)) != 3:
            return "not a triangle of three vertices"
        for e in range(3):
            d = (face[e], face[(e + 1) % 3])
            if d in directed:
                return "an edge traversed twice the same way"
            directed.add(d)
    if any((b, a) not in directed for a, b in directed):
        return "an open edge"
    vol = 0.0
    for a, b, c in f:
        p, q, r = v[a - 1], v[b - 1], v[c - 1]
        vol += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) +
                p[2] * (q[0] * r[1] - q[1] * r[0]))
    return None if vol > 0 else f"volume {vol / 6}"


# ---- mutations: each takes (rng, vertices, faces, text) and returns the file's new text ----

def m_token(rng, v, f, text):          # one number or index replaced by something odd
    lines = text.splitlines()
    i = rng.randrange(len(lines))
    t = lines[i].split()
    if len(t) > 1:
        t[rng.randrange(1, len(t))] = rng.choice(SPECIALS)
        lines[i] = " ".join(t)
    return "\n".join(lines) + "\n"


def m_delete_line(rng, v, f, text):
    lines = text.splitlines()
    del lines[rng.randrange(len(lines))]
    return "\n".join(lines) + "\n"


def m_duplicate_line(rng, v, f, text):
    lines = text.splitlines()
    i = rng.randrange(len(lines))
    lines.insert(rng.randrange(len(lines)), lines[i])
    return "\n".join(lines) + "\n"


def m_swap_lines(rng, v, f, text):
    lines = text.splitlines()
    i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
    lines[i], lines[j] = lines[j], lines[i]
    return "\n".join(lines) + "\n"


def m_truncate(rng, v, f, text):
    return text[:rng.randrange(len(text))]


def m_bytes(rng, v, f, text):          # random bytes spliced in
    b = bytearray(text.encode())
    for _ in range(rng.randint(1, 8)):
        b.insert(rng.randrange(len(b) + 1), rng.randrange(256))
    return bytes(b)


def m_flip_face(rng, v, f, text):
    f = [list(x) for x in f]
    k = rng.randrange(len(f))
    f[k][1], f[k][2] = f[k][2], f[k][1]
    return write_obj(v, f)


def m_inside_out(rng, v, f, text):
    return write_obj(v, [[a, c, b] for a, b, c in f])


def m_collapse(rng, v, f, text):       # two vertices of a face made one
    f = [list(x) for x in f]
    k = rng.randrange(len(f))
    f[k][1] = f[k][0]
    return write_obj(v, f)


def m_move_vertex(rng, v, f, text):    # a vertex thrown across (or far outside) the body
    v = [list(x) for x in v]
    i = rng.randrange(len(v))
    s = rng.choice([-1.5, -1.0, -0.5, 0.0, 0.5, 3.0, 1e6])
    v[i] = [s * x for x in v[i]]
    return write_obj(v, f)


def m_coincide(rng, v, f, text):       # a vertex placed on another (zero-area faces, touching)
    v = [list(x) for x in v]
    i, j = rng.randrange(len(v)), rng.randrange(len(v))
    v[i] = list(v[j])
    return write_obj(v, f)


def m_scale(rng, v, f, text):
    s = rng.choice([1e300, 1e-300, 1e154, 1e-160, -1.0, 0.0])
    return write_obj([[s * x for x in p] for p in v], f)


def m_merge_copy(rng, v, f, text):     # a second copy: apart, touching or overlapping
    size = max(max(p) - min(p) for p in zip(*v))
    d = rng.choice([3.0, 1.0, 0.5, 0.0]) * size
    n = len(v)
    return write_obj(v + [[x + d, y, z] for x, y, z in v], f + [[i + n for i in face] for face in f])


def m_extra_face(rng, v, f, text):     # a face added: non-manifold edge, or a duplicate
    g = list(f)
    face = list(rng.choice(f))
    if rng.random() < 0.5:
        face[2] = rng.randrange(1, len(v) + 1)
    g.append(face)
    return write_obj(v, g)


def m_remove_face(rng, v, f, text):
    g = list(f)
    del g[rng.randrange(len(g))]
    return write_obj(v, g)


def m_polygon(rng, v, f, text):        # a face line with many (or repeated) vertices, fanned
    g = list(f)
    n = rng.choice([4, 5, 50, 10000])
    g.append([rng.randrange(1, len(v) + 1) for _ in range(n)])
    return write_obj(v, g)


def m_index_forms(rng, v, f, text):    # i/t/n and negative indices: the same mesh
    n = len(v)
    out = "".join(f"v {a!r} {b!r} {c!r}\nvt 0 0\nvn 0 0 1\n" for a, b, c in v)
    for face in f:
        out += "f " + " ".join(rng.choice([f"{i}/{i}/{i}", f"{i}//{i}", str(i - n - 1)]) for i in face) + "\n"
    return out


def m_empty(rng, v, f, text):
    return rng.choice(["", "# nothing\n", "v 0 0 0\n", "f 1 2 3\n", "\n" * 1000, "o object\ng group\n"])


MUTATIONS = [m_token, m_delete_line, m_duplicate_line, m_swap_lines, m_truncate, m_bytes, m_flip_face,
             m_inside_out, m_collapse, m_move_vertex, m_coincide, m_scale, m_merge_copy, m_extra_face,
             m_remove_face, m_polygon, m_index_forms, m_empty]


def limit_resources():
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))


def run_case(noether, work, name, shape_key, size):
    scene = work / f"{name}.yaml"
    probe = 20 * size if size > 0 else 1000
    scene.write_text(SCENE.format(shape=shape_key, probe=probe, speed=1e-4))
    t = time.monotonic()
    try:
        p = subprocess.run([noether, "run", str(scene), "--no-progress", "--summary", "json"],
                           capture_output=True, text=True, errors="replace", timeout=TIME_LIMIT,
                           preexec_fn=limit_resources)
    except subprocess.TimeoutExpired:
        return "hang", f"more than {TIME_LIMIT} s", time.monotonic() - t
    return p.returncode, (p.stdout, p.stderr), time.monotonic() - t


def reason(message):
    """A refusal's kind: its last clause, numbers and quoted text elided."""
    text = re.sub(r"'[^']*'", "'…'", message.split(": ")[-1])
    return re.sub(r"-?[0-9][0-9.e+-]*", "N", text)[:70]


def classify(code, out, mesh_names, valid_check):
    """(outcome, finding or None)"""
    if code == "hang":
        return "hang", out
    stdout, stderr = out
    if code < 0:
        return "crash", f"signal {-code}: {stderr[-500:]}"
    if code == 0:
        problem = valid_check()
        if problem:
            return "accepted", f"accepted a mesh that is not a closed outward surface ({problem})"
        try:
            summary = json.loads(stdout)
        except ValueError:
            return "accepted", f"no JSON summary: {stdout[-300:]}"
        if not all(isinstance(x, (int, float)) and x == x and abs(x) != float("inf")
                   for x in summary.values() if isinstance(x, float)):
            if summary.get("verdict") == "trustworthy":
                return "accepted", f"non-finite summary numbers with a trustworthy verdict: {summary}"
        return "accepted", None
    if code == 2:
        lines = [l for l in stderr.splitlines() if l.startswith("noether:")]
        if not lines:
            return "refused", f"exit 2 without a 'noether:' message: {stderr[-300:]}"
        msg = lines[-1]
        if len(msg) > 2000 or any(ord(c) < 0x20 or ord(c) == 0x7f for c in msg):
            return "refused", f"the message is {len(msg)} characters or holds control bytes: {msg[:300]!r}"
        if "overlap at the start" in msg:  # a valid mesh, moved onto the probe
            return "refused: " + reason(msg), None
        if not re.match(r"noether: .*\.yaml:5: body 'rock': ", msg):
            return "refused", f"the refusal does not name the scene's line and body: {msg}"
        if not any(n in msg for n in mesh_names):
            return "refused", f"the refusal does not name the shape file: {msg}"
        return "refused: " + reason(msg), None
    if code == 3:  # the run failed (e.g. a probe inside a body thrown out to 1e6 of its size)
        if not any(l.startswith("noether:") for l in stderr.splitlines()):
            return "run failed", f"exit 3 without a 'noether:' message: {stderr[-300:]}"
        return "run failed", None
    return f"exit {code}", f"unexpected exit {code}: {stderr[-500:]}"


def main():
    noether, source, work = sys.argv[1], pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
    cases = int(sys.argv[4]) if len(sys.argv) > 4 else 600
    seed = int(sys.argv[5]) if len(sys.argv) > 5 else 1
    work.mkdir(parents=True, exist_ok=True)
    rng = random.Random(seed)
    shapes = source / "examples" / "shapes"
    seeds = []
    for name in ["fahnestock2006_B1.obj", "fahnestock2006_B2.obj", "hou2017_A.obj", "hou2017_B.obj"]:
        v, f = read_obj(shapes / name)
        scale = 1000.0 if name.startswith("hou") else 1.0
        seeds.append((name, [[scale * x for x in p] for p in v], f))
    seeds.append(("icosphere-2", *icosphere(2)))
    seeds.append(("icosphere-4", *icosphere(4)))

    jobs = []  # (name, shape_key, size, mesh_names, valid_check)
    for k in range(cases):
        base, v, f = seeds[k % len(seeds)]
        mutate = rng.choice(MUTATIONS)
        text = mutate(rng, v, f, write_obj(v, f))
        path = work / f"case-{k:04d}.obj"
        (path.write_bytes if isinstance(text, bytes) else path.write_text)(text)
        size = max(max(p) - min(p) for p in zip(*v))

        def check(path=path):
            try:
                mv, mf = read_obj(path)
            except (ValueError, IndexError, UnicodeDecodeError) as e:
                return f"unreadable by the independent reader: {e}"
            return independent_check(mv, mf)
        jobs.append((f"case-{k:04d}", f"file: {path.name}", size, [path.name], check, f"{base} {mutate.__name__}"))
    # The CSV pair (GUBAS's format): mutated vertex and facet files.
    v, f = icosphere(2)
    for k in range(cases // 10):
        vt = "".join(f"{i + 1}, {a!r}, {b!r}, {c!r}\n" for i, (a, b, c) in enumerate(v))
        ft = "".join(f"{a}, {b}, {c}\n" for a, b, c in f)
        which = rng.choice(["v", "f"])
        lines = (vt if which == "v" else ft).splitlines()
        i = rng.randrange(len(lines))
        fields = lines[i].split(",")
        op = rng.choice(["token", "drop", "extra", "delete"])
        if op == "token":
            fields[rng.randrange(len(fields))] = rng.choice(SPECIALS + ["0", "1.5", str(len(v) + 1)])
        elif op == "drop":
            fields.pop()
        elif op == "extra":
            fields.append("7")
        lines[i] = ",".join(fields)
        if op == "delete":
            del lines[i]
        text = "\n".join(lines) + "\n"
        vp, fp = work / f"csv-{k:03d}-vert.csv", work / f"csv-{k:03d}-facet.csv"
        vp.write_text(text if which == "v" else vt)
        fp.write_text(text if which == "f" else ft)
        jobs.append((f"csv-{k:03d}", f"vertices: {vp.name}, facets: {fp.name}", 100.0, [vp.name, fp.name],
                     lambda: None, f"csv {which} {op}"))
        # An accepted CSV pair is checked by the reader being strict: no independent check.

    # Large and hostile files: a 1.3-million-face sphere (accepted within the limits), one face
    # over the bound, a device, a sparse file over the byte bound, one 100 MB line.
    big = work / "sphere-1.3M.obj"
    bv, bf = icosphere(8)
    big.write_text(write_obj(bv, bf))
    jobs.append(("big-sphere", f"file: {big.name}", 100.0, [big.name], lambda: None, "1,310,720 faces"))
    over = work / "over-bound.obj"
    with open(over, "w") as o:
        o.write("v 1 0 0\nv 0 1 0\nv 0 0 1\nf" + " 1 2 3" * ((1 << 22) // 3 + 2) + "\n")
    jobs.append(("over-bound", f"file: {over.name}", 1.0, [over.name], lambda: "accepted", "4,194,307 faces"))
    jobs.append(("device", "file: /dev/zero", 1.0, ["/dev/zero"], lambda: "accepted", "/dev/zero"))
    sparse = work / "sparse.obj"
    with open(sparse, "w") as o:
        o.truncate((1 << 30) + 1)
    jobs.append(("sparse", f"file: {sparse.name}", 1.0, [sparse.name], lambda: "accepted", "1 GiB + 1 sparse"))
    long_line = work / "long-line.obj"
    with open(long_line, "w") as o:
        o.write("v 1 0 0\nv " + "1" * 100_000_000 + " 0 0\n")
    jobs.append(("long-line", f"file: {long_line.name}", 1.0, [long_line.name], lambda: "accepted", "100 MB line"))

    counts, findings, slowest = {}, [], (0.0, "")

    def one(job):
        name, key, size, names, check, what = job
        code, out, seconds = run_case(noether, work, name, key, size)
        outcome, finding = classify(code, out, names, check)
        return name, what, outcome, finding, seconds

    with ThreadPoolExecutor(max_workers=2) as pool:
        for name, what, outcome, finding, seconds in pool.map(one, jobs):
            counts[outcome] = counts.get(outcome, 0) + 1
            slowest = max(slowest, (seconds, f"{name} ({what})"))
            if finding:
                findings.append(f"{name} ({what}): {finding}")
    total = lambda prefix: sum(n for k, n in counts.items() if k.startswith(prefix))
    print(f"fuzz_meshes: {len(jobs)} files (seed {seed}): {total('accepted')} accepted, "
          f"{total('refused')} refused, {total('run failed')} failed runs, "
          f"{len(jobs) - total('accepted') - total('refused') - total('run failed')} other; "
          f"slowest {slowest[0]:.1f} s: {slowest[1]}")
    for k, n in sorted(counts.items(), key=lambda kv: -kv[1]):
        if k.startswith("refused: "):
            print(f"  {n:5d}  {k[9:]}")
    for f in findings:
        print("FINDING:", f)
    for p in work.glob("*.obj"):
        if p.stat().st_size > 10_000_000:
            p.unlink()
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
