#!/usr/bin/python3
"""Benchmark: a stiff rod on lateral springs in a coaxial cylinder of water, through `tetfsi run`.

    scripts/bench_coaxial_rod.py --tetfsi build/apps/tetfsi [--out DIR] [--quick]

Runs data/scenes/coaxial_rod_ci.json (rod length L = 3b, edge a/3 at the rod), the same scene
with edge a/5 and a/7, and data/scenes/coaxial_rod.json (the benchmark: L = 6b, edge a/7), measures the transverse oscillation
frequency from the zero crossings of the rod centre's x displacement (probes.csv) and prints one
table: case, resolution, frequency error against f = (1/2 pi) sqrt(k / (m + m_a)) with the
coaxial-cylinder added mass m_a = rho pi a^2 L (b^2 + a^2) / (b^2 - a^2), wall time and peak memory
of the run. --quick skips the benchmark resolution.
"""

import argparse
import csv
import json
import math
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = os.path.join(HERE, "..", "data", "scenes")


def reference(scene):
    """Exact frequency, in-vacuum frequency [Hz] and m_a / m of the scene's rod."""
    rod = scene["solids"][0]
    a, length = rod["geometry"]["radius"], rod["geometry"]["length"]
    b = scene["domain"]["container"]["radius"]
    k = sum(s["stiffness"] for s in rod["springs"])
    m = rod["material"]["density"] * math.pi * a * a * length
    m_a = scene["fluid"]["density"] * math.pi * a * a * length * (b * b + a * a) / (b * b - a * a)
    return math.sqrt(k / (m + m_a)) / (2 * math.pi), math.sqrt(k / m) / (2 * math.pi), m_a / m


def crossing_frequency(probes):
    """Frequency from the zero crossings of centre_x after t = 0 (linear interpolation)."""
    rows = list(csv.DictReader(open(probes)))
    t = [float(r["time"]) for r in rows]
    x = [float(r["centre_x"]) for r in rows]
    at = [t[i - 1] + (t[i] - t[i - 1]) * x[i - 1] / (x[i - 1] - x[i])
          for i in range(1, len(t)) if (x[i - 1] > 0 >= x[i]) or (x[i - 1] < 0 <= x[i])]
    if len(at) < 3:
        sys.exit(f"{probes}: fewer than {len(at)} zero crossings")
    return (len(at) - 1) / (2 * (at[-1] - at[0]))


def run(tetfsi, scene, out):
    """Runs the scene; returns (wall time [s], peak memory [MB], fluid tets)."""
    path = os.path.join(out, "scene.json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    start = time.monotonic()
    p = subprocess.Popen([tetfsi, "run", path, "--out", os.path.join(out, "run"), "--quiet"],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    log = p.stdout.read()
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.monotonic() - start
    if status != 0:
        sys.exit(f"FAILED: {tetfsi} run {path}\n{log}")
    fluid_tets = 0
    for line in open(os.path.join(out, "run", "run.log")):
        if "coupled model:" in line:
            fluid_tets = int(line.split(" fluid tets")[0].split()[-1])
    return wall, usage.ru_maxrss / 1024, fluid_tets


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tetfsi", required=True)
    ap.add_argument("--out", default="bench_coaxial_rod")
    ap.add_argument("--quick", action="store_true", help="skip the benchmark resolution")
    args = ap.parse_args()
    ci = json.load(open(os.path.join(SCENES, "coaxial_rod_ci.json")))
    bench = json.load(open(os.path.join(SCENES, "coaxial_rod.json")))
    cases = [("coaxial_rod_ci", ci)]
    for edge in (0.01, 0.007):  # the CI scene (L = 3b) refined: edge a/5, a/7 at the rod
        finer = json.loads(json.dumps(ci))
        finer["mesh"]["edge_length_near_solids"], finer["mesh"]["edge_length"] = edge, 1.5 * edge
        cases.append((f"coaxial_rod_ci, edge {edge:g}", finer))
    if not args.quick:
        cases.append(("coaxial_rod", bench))
    print("| case | resolution | error vs reference | wall time [s] | peak memory [MB] |")
    print("|---|---|---|---|---|")
    for i, (name, scene) in enumerate(cases):
        out = os.path.join(args.out, str(i))
        os.makedirs(out, exist_ok=True)
        wall, mem, tets = run(args.tetfsi, scene, out)
        exact, vacuum, ratio = reference(scene)
        f = crossing_frequency(os.path.join(out, "run", "probes.csv"))
        a = scene["solids"][0]["geometry"]["radius"]
        length = scene["solids"][0]["geometry"]["length"]
        res = (f"L = {length:g} m, edge {scene['mesh']['edge_length_near_solids']:g} m = a/{a / scene['mesh']['edge_length_near_solids']:.1f} "
               f"at the rod, {tets} fluid tets, dt {scene['simulation']['dt']:g} s")
        print(f"| {name} (m_a/m = {ratio:.3f}, f_vac/f = {vacuum / exact:.3f}) | {res} | "
              f"{f / exact - 1:+.2e} rel. (frequency {f:.4f} Hz, exact {exact:.4f} Hz) | {wall:.1f} | {mem:.1f} |",
              flush=True)


if __name__ == "__main__":
    main()
