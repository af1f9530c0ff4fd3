#!/usr/bin/env python3
"""validate and run give the same verdict on bad scenes (issue 18).

Generates bad scenes by mutating the scenes of data/scenes (numbers set to out-of-range,
huge, tiny or wrongly typed values; required keys removed; unknown keys added; names and
probes broken; surfaces cut), deterministically from a seed, and runs `tetfsi validate` and
`tetfsi run`, both with --end-time 1e-4, on each (plus every *.json of the folders given with --extra).
A case passes when neither crashes, hangs or reports an internal error, run exits 2 exactly
when validate does (validate 0 with run 1, a physics failure, is allowed), and every exit-2
message names a key (a JSON pointer) or a file.

  scripts/bad_inputs.py --tetfsi build/apps/tetfsi [--count 220 | --per-base 5] [--seed 18] [--extra DIR ...]
                        [--timeout 60] [--only 'paddle:']
--per-base N takes N mutants of each base scene instead of --count drawn from all: a fixed
amount of work whatever the draw (ctest's sample), since the bases cost very different times to mesh.
Exit code 0 if every case passes; the failures are listed.
"""
import argparse
import concurrent.futures
import copy
import json
import os
import random
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BASES = ["soft_drop", "light_ball_in_water", "paddle", "cantilever", "block_compression", "spinning_sheet",
         "gas_expansion_ci", "filled_toy_ci"]
BAD_NUMBERS = [-1, 0, 1e300, -1e300, 1e-320, 1e19, -9.2e18, 1e15, "x", None, True, [1, 2], {}]


def leaves(node, path=()):
    if isinstance(node, dict):
        for k, v in node.items():
            yield from leaves(v, path + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from leaves(v, path + (i,))
    else:
        yield path, node


def keys(node, path=()):
    if isinstance(node, dict):
        for k, v in node.items():
            yield path + (k,)
            yield from keys(v, path + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from keys(v, path + (i,))


def get_parent(doc, path):
    for p in path[:-1]:
        doc = doc[p]
    return doc


def mutations(scene, rng):
    """Yields (label, mutated scene or raw text)."""
    for path, value in leaves(scene):
        if isinstance(value, (int, float)) and not isinstance(value, bool) and path[0] != "description":
            for bad in rng.sample(BAD_NUMBERS, 3):
                s = copy.deepcopy(scene)
                get_parent(s, path)[path[-1]] = bad
                yield "/".join(map(str, path)) + "=" + json.dumps(bad), s
    for path in keys(scene):
        if isinstance(path[-1], str):
            s = copy.deepcopy(scene)
            del get_parent(s, path)[path[-1]]
            yield "del " + "/".join(map(str, path)), s
    s = copy.deepcopy(scene)
    s["simulation"]["end_tme"] = 1
    yield "unknown key", s
    s = copy.deepcopy(scene)
    s["k" * 100000] = 1
    yield "huge unknown key", s
    for name in ["fluid", "stats.csv", "a" * 300, "a b", "", "../x", "membrane"]:
        if scene.get("solids"):
            s = copy.deepcopy(scene)
            s["solids"][0]["name"] = name
            yield "solid name " + name[:20], s
    for pname in ["a,b", "time", "", 'q"uote']:
        s = copy.deepcopy(scene)
        s["probes"] = [{"name": pname, "kind": "total_energy"}]
        yield "probe name " + pname, s
    for kind in ["fluid_point", "fluid_kinetic_energy", "fluid_volume", "solid_volume", "sphere_top_z"]:
        s = copy.deepcopy(scene)
        p = {"name": "p", "kind": kind}
        if kind == "fluid_point":
            p.update({"point": [0, 0, 0], "quantity": "speed"})
        if kind == "solid_volume" and scene.get("solids"):
            p["solid"] = scene["solids"][0]["name"]
        s["probes"] = [p]
        yield "probe " + kind, s
    text = json.dumps(scene)
    yield "cut JSON", text[: len(text) // 2]
    yield "not JSON", "{\"simulation\": [}"


RUN_TIMEOUT = 60  # seconds per validate or run (--timeout)


def run(cmd, timeout=None):
    timeout = timeout or RUN_TIMEOUT
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, errors="replace")
        return p.returncode, p.stdout + p.stderr
    except subprocess.TimeoutExpired:
        return "timeout", ""


def check(tetfsi, scene_file, workdir):
    v, vout = run([tetfsi, "validate", scene_file, "--end-time", "1e-4"])
    r, rout = run([tetfsi, "run", scene_file, "--out", os.path.join(workdir, "out"), "--quiet", "--threads", "1",
                   "--end-time", "1e-4"])
    problems = []
    for name, code, out in (("validate", v, vout), ("run", r, rout)):
        if code not in (0, 1, 2):
            problems.append(f"{name}: exit {code}")
        if "internal error" in out:
            problems.append(f"{name}: internal error")
        if code == 2 and not re.search(r"(: /[A-Za-z_]|\.(json|ply|obj|stl|off)\b|--[a-z])", out):
            problems.append(f"{name}: exit 2 without a key or a file: {out[:200]!r}")
    if (v == 2) != (r == 2):
        problems.append(f"validate exit {v}, run exit {r}: {(vout if v == 2 else rout)[:300]!r}")
    return v, r, problems


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tetfsi", default=os.path.join(ROOT, "build", "apps", "tetfsi"))
    ap.add_argument("--count", type=int, default=220)
    ap.add_argument("--per-base", type=int, default=0, help="N mutants of each base scene (instead of --count)")
    ap.add_argument("--seed", type=int, default=18)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--extra", nargs="*", default=[])
    ap.add_argument("--timeout", type=float, default=60,
                    help="seconds each validate and run may take (a sanitizer build needs about 10x)")
    ap.add_argument("--only", default="",
                    help="run only the selected cases whose label starts with this (e.g. 'paddle:')")
    args = ap.parse_args()
    global RUN_TIMEOUT
    RUN_TIMEOUT = args.timeout
    rng = random.Random(args.seed)
    tmp = tempfile.mkdtemp(prefix="tetfsi_bad_inputs_")
    cases = []
    for base in BASES:
        path = os.path.join(ROOT, "data", "scenes", base + ".json")
        scene = json.load(open(path))
        for label, mutated in mutations(scene, rng):
            cases.append((base + ": " + label, mutated, os.path.dirname(path)))
    rng.shuffle(cases)
    if args.per_base > 0:
        cases = [c for base in BASES for c in [c for c in cases if c[0].startswith(base + ": ")][: args.per_base]]
    else:
        cases = cases[: args.count]
    # A cut PLY and a header-only PLY as a solid's surface.
    for name, content in (("cut.ply", "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
                                      "property float z\nelement face 12\nproperty list uchar int vertex_indices\n"
                                      "end_header\n0 0 0\n1 0"), ("header_only.ply", "ply\nformat ascii 1.0\n")):
        open(os.path.join(tmp, name), "w").write(content)
        s = json.load(open(os.path.join(ROOT, "data", "scenes", "soft_drop.json")))
        s["solids"][0]["geometry"] = {"type": "mesh", "file": os.path.join(tmp, name)}
        cases.append(("surface " + name, s, tmp))
    # Cut volume mesh files as a solid's tets.
    for name, content in (("cut.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n"),
                          ("cut.vtu", '<VTKFile type="UnstructuredGrid"><UnstructuredGrid><Piece NumberOfPoints="4" '
                                      'NumberOfCells="1"><Points><DataArray type="Float64" NumberOfComponents="3" '
                                      'format="ascii">0 0 0 1 0')):
        open(os.path.join(tmp, name), "w").write(content)
        s = json.load(open(os.path.join(ROOT, "data", "scenes", "soft_drop.json")))
        s["solids"][0]["geometry"] = {"type": "volume_mesh", "file": os.path.join(tmp, name)}
        cases.append(("volume mesh " + name, s, tmp))
    files = []
    for i, (label, scene, folder) in enumerate(cases):
        if not label.startswith(args.only):
            continue
        d = os.path.join(tmp, f"case{i:04d}")
        os.makedirs(d)
        f = os.path.join(d, "scene.json")
        text = scene if isinstance(scene, str) else json.dumps(scene)
        # relative surface files of data/scenes stay reachable: absolute paths
        text = text.replace('"file": "', '"file": "' + folder + "/") if '"file": "/' not in text else text
        open(f, "w").write(text)
        files.append((label, f, d))
    for extra in args.extra:
        for name in sorted(os.listdir(extra)):
            if name.endswith(".json"):
                d = os.path.join(tmp, f"extra_{len(files):04d}")
                os.makedirs(d)
                files.append((os.path.join(extra, name), os.path.join(extra, name), d))
    failures, counts = [], {}
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        results = pool.map(lambda c: (c[0],) + check(args.tetfsi, c[1], c[2]), files)
        for label, v, r, problems in results:
            counts[(v, r)] = counts.get((v, r), 0) + 1
            if problems:
                failures.append((label, problems))
    print(f"{len(files)} scenes; (validate, run) exit codes: " +
          ", ".join(f"{k}: {n}" for k, n in sorted(counts.items(), key=str)))
    for label, problems in failures:
        print(f"FAIL {label}: " + "; ".join(problems))
    subprocess.run(["rm", "-rf", tmp])
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
