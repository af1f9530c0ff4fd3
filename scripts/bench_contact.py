#!/usr/bin/env python3
"""Cost of a coupled step with active solid-solid contact against the same step without it.

Two soft balls in a closed tank of water (data/scenes/balls_collide.json), started 4 mm more than
the contact film (coupling.contact_gap, set to half the near-solid edge) apart: closing at 2 m/s they are in contact
(coupling.solid_contact, surface contact inside eq. 7) from about the third step on; the same balls
separating at 2 m/s, on the same mesh, have none. The table
compares the mean wall time of a step (sum of the stats.csv phase columns) over the steps in which
the closing pair has contacts, with the phases that make it up and the mean contact rounds (each
round is one more solve of eq. 7). The error column is the left/right asymmetry of the closing run,
|d_left + d_right| / |d_left| of the two centres at the end: the set-up is mirror-symmetric, so it
measures the mesh's asymmetry and the solver tolerance, not the contact.

Usage: scripts/bench_contact.py [--build build] [--levels 0 1 2 3]   (level 3: about 100k tets)
Prints the common benchmark table (apps/bench/bench_support.hpp) plus the step-cost ratio.
"""
import argparse
import csv
import json
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# (edge length far from the balls, near them) [m]; about 4k, 15k, 60k and 100k tets in all.
LEVELS = [(0.12, 0.025), (0.08, 0.016), (0.05, 0.0105), (0.042, 0.0088)]


def scene(level, closing):
    with open(os.path.join(ROOT, "data/scenes/balls_collide.json")) as f:
        s = json.load(f)
    far, near = LEVELS[level]
    s["mesh"].update({"edge_length": far, "edge_length_near_solids": near, "facet_distance": near / 10})
    s["simulation"].update({"end_time": 0.012, "dt": 0.001, "frame_rate": 1000 / 12})
    s["export"] = {"vtu": False, "surfaces": "none"}
    s["coupling"]["contact_gap"] = 0.5 * near
    speed = 1.0 if closing else -1.0
    centre = 0.1 + 0.5 * (0.5 * near + 0.004)
    for solid, side in zip(s["solids"], (-1, 1)):
        solid["placement"]["translation"] = [side * centre, 0, 0]
        solid["initial_velocity"] = [-side * speed, 0, 0]
    s["probes"] = [p for p in s["probes"] if p["kind"] == "point_displacement"]
    for p, side in zip(s["probes"], (-1, 1)):
        p["point"] = [side * centre, 0, 0]
    return s


def run(binary, s, folder, name):
    path = os.path.join(folder, name + ".json")
    with open(path, "w") as f:
        json.dump(s, f)
    out = os.path.join(folder, name)
    mem = os.path.join(folder, name + ".mem")
    subprocess.run(["/usr/bin/time", "-f", "%M", "-o", mem, binary, "run", path, "--out", out, "--quiet"],
                   check=True)
    with open(os.path.join(out, "stats.csv")) as f:
        stats = list(csv.DictReader(f))
    with open(os.path.join(out, "probes.csv")) as f:
        probes = list(csv.DictReader(f))
    with open(mem) as f:
        peak_mb = float(f.read().split()[-1]) / 1024
    with open(os.path.join(out, "run.log")) as f:
        tets = re.search(r"mesh quality: (\d+) tets", f.read()).group(1)
    return stats, probes, peak_mb, tets


def step_seconds(row):
    return sum(float(v) for k, v in row.items() if k.startswith("t_") and k != "t_output")


def phases(rows, steps):
    """Mean seconds per step of each phase column, as "remesh 0.01, solve 0.2, ..."."""
    names = [k for k in rows[0] if k.startswith("t_") and k != "t_output"]
    return ", ".join(f"{k[2:]} {sum(float(rows[i][k]) for i in steps) / len(steps):.3f}" for k in names)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--levels", type=int, nargs="+", default=[0, 1, 2, 3])
    args = ap.parse_args()
    binary = os.path.join(args.build, "apps/tetfsi")
    print("| case | resolution | error vs reference | wall time [s] | peak memory [MB] |")
    print("|---|---|---|---|---|")
    ratios = []
    with tempfile.TemporaryDirectory() as folder:
        for level in args.levels:
            closing, probes, mem_c, tets = run(binary, scene(level, True), folder, f"closing{level}")
            apart, _, mem_a, _ = run(binary, scene(level, False), folder, f"apart{level}")
            steps = [i for i, r in enumerate(closing) if float(r["contacts"]) > 0 and i < len(apart)]
            if not steps:
                sys.exit(f"level {level}: the closing balls never touched")
            with_contact = sum(step_seconds(closing[i]) for i in steps) / len(steps)
            without = sum(step_seconds(apart[i]) for i in steps) / len(steps)
            last = probes[-1]
            dl, dr = float(last["left_centre_x"]), float(last["right_centre_x"])
            sym = abs(dl + dr) / abs(dl)
            resolution = f"{tets} tets ({closing[0]['fluid_tets']} fluid)"
            contacts = max(int(float(r["contacts"])) for r in closing)
            mean_rounds = sum(float(closing[i]["contact_rounds"]) for i in steps) / len(steps)
            print(f"| balls closing, contact in {len(steps)} steps (up to {contacts} pairs, mean "
                  f"{mean_rounds:.1f} rounds, {phases(closing, steps)}) | {resolution} | asymmetry {sym:.1e} | "
                  f"{with_contact:.3f} per step | {mem_c:.1f} |")
            apart_contacts = sum(1 for i in steps if float(apart[i]["contacts"]) > 0)
            print(f"| balls separating, contact in {apart_contacts} of the same steps ({phases(apart, steps)}) | {resolution} "
                  f"| - | {without:.3f} per step | {mem_a:.1f} |")
            ratios.append((resolution, with_contact / without))
            sys.stdout.flush()
    for resolution, r in ratios:
        print(f"step cost with contact / without: {r:.2f} at {resolution}")


if __name__ == "__main__":
    main()
