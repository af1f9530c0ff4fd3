#!/usr/bin/env python3
"""Solids through the fluid to rest: a ball released at rest in a closed tank of water.

The scenes are written here from the scene reference (docs/scene_format.md), as a user writes
them: a ball of radius 0.1 m (icosphere level 3, neo-Hookean, nu = 0.3) at the centre of a closed
tank 0.8 m across full of water (inviscid), for every combination of
  - container: the domain box, a sphere, a cylinder (axis vertical), or the box given as a surface
    file (a cube OBJ written here);
  - density ratio rho_s / rho_f;
  - Young's modulus E (soft 1e5 Pa, stiff 1e8 Pa);
  - time step h (the paper's 1/30 s and finer),
with the container's walls as contact obstacles through the default fluid film (coupling/README.md).
With --damping BETA the rubber has Rayleigh damping beta [s] (its own losses), so that a ball comes
to rest within the run; without, only the scheme's and the fluid's numerical dissipation act.

Per run it reports the exit code; the largest change of the ball's volume (the water cannot change
its volume, so the ball may not: coupling/closed_regions.hpp) and of the closed water's volume
(stats.csv closed_volume_error); the deepest penetration of a node into the wall film
(stats.csv wall_clearance, negative inside) as a fraction of the near-solid edge; where the ball
rests (the gap between its nearest node and the wall, against the film) and the wall force at the
end against Archimedes, (rho_s - rho_f) V g with the meshed volume V (contact_force probe); the
largest rebound after the first impact; and the cost of a step with contact against one without
(the mean of stats.csv's phase columns over the steps with and without contacts, the same run).

Usage: scripts/bench_contact_sweep.py [--tetfsi build/apps/tetfsi] [--containers box sphere ...]
       [--ratios ...] [--stiffness ...] [--dts ...] [--end 1.5] [--damping 0.01] [--edge 0.054]
Prints one table (the common benchmark columns first: case, resolution, error vs reference, wall
time, peak memory; then the contact columns).
"""
import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
R_BALL, HALF, RHO_F, G = 0.1, 0.4, 1000.0, 9.81


def cube_obj(path):
    """A closed cube [-HALF, HALF]^3 as a triangle OBJ, outward faces."""
    corners = [(x, y, z) for x in (-HALF, HALF) for y in (-HALF, HALF) for z in (-HALF, HALF)]
    index = {c: i + 1 for i, c in enumerate(corners)}
    quads = [((-1, -1, -1), (-1, -1, 1), (-1, 1, 1), (-1, 1, -1)), ((1, -1, -1), (1, 1, -1), (1, 1, 1), (1, -1, 1)),
             ((-1, -1, -1), (1, -1, -1), (1, -1, 1), (-1, -1, 1)), ((-1, 1, -1), (-1, 1, 1), (1, 1, 1), (1, 1, -1)),
             ((-1, -1, -1), (-1, 1, -1), (1, 1, -1), (1, -1, -1)), ((-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1))]
    with open(path, "w") as f:
        for c in corners:
            f.write("v %g %g %g\n" % c)
        for q in quads:
            a, b, c, d = (index[tuple(HALF * s for s in p)] for p in q)
            f.write(f"f {a} {b} {c}\nf {a} {c} {d}\n")


def scene(container, ratio, stiffness, dt, end, damping, edge, folder):
    s = {
        "simulation": {"end_time": end, "dt": dt, "frame_rate": 30, "gravity": [0, -G, 0]},
        "domain": {"lo": [-HALF] * 3, "hi": [HALF] * 3},
        "mesh": {"edge_length": 0.15, "edge_length_near_solids": edge, "grading_distance": 0.25},
        "fluid": {"type": "liquid", "density": RHO_F},
        "solids": [{"name": "ball", "geometry": {"type": "sphere", "radius": R_BALL, "subdivisions": 3},
                    "material": {"density": ratio * RHO_F, "youngs_modulus": stiffness, "poissons_ratio": 0.3,
                                 "constitutive": "neohookean"}}],
        "probes": [{"name": "centre", "kind": "point_displacement", "solid": "ball", "point": [0, 0, 0]},
                   {"name": "ball_volume", "kind": "solid_volume", "solid": "ball"},
                   {"name": "wall_force", "kind": "contact_force", "solid": "ball"}],
        "export": {"vtu": False, "surfaces": "none"},
    }
    if damping > 0:
        s["solids"][0]["material"]["rayleigh_beta"] = damping
    if container != "box":
        s["domain"] = {"lo": [-1.03 * HALF] * 3, "hi": [1.03 * HALF] * 3}
    if container == "sphere":
        s["domain"]["container"] = {"type": "sphere", "center": [0, 0, 0], "radius": HALF}
    elif container == "cylinder":
        s["domain"]["container"] = {"type": "cylinder", "center": [0, 0, 0], "radius": HALF, "length": 2 * HALF,
                                    "axis": "y"}
    elif container == "mesh":
        cube = os.path.join(folder, "cube.obj")
        if not os.path.exists(cube):
            cube_obj(cube)
        s["domain"]["container"] = {"type": "mesh", "file": cube}
    return s


def run(binary, s, folder, name):
    path = os.path.join(folder, name + ".json")
    with open(path, "w") as f:
        json.dump(s, f)
    out = os.path.join(folder, name)
    mem = os.path.join(folder, name + ".mem")
    start = time.time()
    p = subprocess.run(["/usr/bin/time", "-f", "%M", "-o", mem, binary, "run", path, "--out", out, "--quiet"],
                       capture_output=True, text=True)
    wall = time.time() - start
    result = {"status": p.returncode, "wall": wall, "message": (p.stdout + p.stderr).strip().splitlines()[-1:]}
    try:
        with open(mem) as f:
            result["peak_mb"] = float(f.read().split()[-1]) / 1024
    except (OSError, ValueError, IndexError):
        result["peak_mb"] = float("nan")
    try:
        with open(os.path.join(out, "stats.csv")) as f:
            result["stats"] = list(csv.DictReader(f))
        with open(os.path.join(out, "probes.csv")) as f:
            result["probes"] = list(csv.DictReader(f))
        with open(os.path.join(out, "run.log")) as f:
            log = f.read()
        result["film"] = float(re.search(r"fluid film ([0-9.eE+-]+) m", log).group(1))
        result["tets"] = int(re.search(r"mesh quality: (\d+) tets", log).group(1))
    except (OSError, AttributeError):
        pass
    return result


def step_seconds(row):
    return sum(float(v) for k, v in row.items() if k.startswith("t_") and k != "t_output")


def summary(r, ratio):
    """The table's measured columns of one run."""
    if "stats" not in r or not r["stats"]:
        return None
    stats, probes = r["stats"], r["probes"]
    v0 = float(probes[0]["ball_volume"])
    ball = max(abs(float(p["ball_volume"]) / v0 - 1) for p in probes)
    water = max(abs(float(s["closed_volume_error"])) for s in stats)
    clearance = min(float(s["wall_clearance"]) for s in stats)
    edge = 2 * r["film"]  # the film is half the near-solid edge as meshed
    # Rest: the centre's distance to the wall it rests on (floor for a heavy ball, lid for a
    # light one) less the radius, against the film; the wall force against Archimedes.
    y = [float(p["centre_y"]) for p in probes]
    heavy = ratio > 1
    gap = (y[-1] + HALF - R_BALL) if heavy else (HALF - R_BALL - y[-1])
    volume = float(probes[-1]["ball_volume"])
    expected = (ratio - 1) * RHO_F * volume * G
    force = float(probes[-1]["wall_force_y"])
    # Rebound: the largest rise off the first impact (the centre's first turn towards the wall).
    sign = 1 if heavy else -1
    path = [sign * v for v in y]
    first = next((i for i in range(1, len(path) - 1) if path[i] <= path[i - 1] and path[i] < path[i + 1]), None)
    rebound = max(path[first:]) - path[first] if first is not None else 0.0
    contact = [step_seconds(s) for s in stats if float(s["contacts"]) > 0]
    free = [step_seconds(s) for s in stats[1:] if float(s["contacts"]) == 0]
    cost = (sum(contact) / len(contact)) / (sum(free) / len(free)) if contact and free else float("nan")
    substeps = max(int(float(s["substeps"])) for s in stats)
    return {"ball": ball, "water": water, "penetration": max(0.0, -clearance) / edge, "gap": gap,
            "film": r["film"], "force_error": force / expected - 1 if expected else float("nan"),
            "rebound": rebound, "cost": cost, "substeps": substeps}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tetfsi", default=os.path.join(ROOT, "build/apps/tetfsi"))
    ap.add_argument("--containers", nargs="+", default=["box", "sphere", "cylinder", "mesh"])
    ap.add_argument("--ratios", type=float, nargs="+", default=[0.01, 0.1, 0.5, 2, 10, 100])
    ap.add_argument("--stiffness", type=float, nargs="+", default=[1e5, 1e8])
    ap.add_argument("--dts", type=float, nargs="+", default=[1 / 30, 1 / 120])
    ap.add_argument("--end", type=float, default=1.5)
    ap.add_argument("--damping", type=float, default=0.01, help="Rayleigh beta of the rubber [s]; 0: none")
    ap.add_argument("--edge", type=float, default=0.054, help="mesh.edge_length_near_solids [m]")
    args = ap.parse_args()
    print("| case | resolution | error vs reference | wall time [s] | peak memory [MB] | exit | ball volume | "
          "water volume | penetration / edge | rest gap (film) | rebound | substeps | contact step cost |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for container in args.containers:
            for stiffness in args.stiffness:
                for ratio in args.ratios:
                    for dt in args.dts:
                        name = f"{container}_r{ratio:g}_E{stiffness:g}_h1over{round(1 / dt)}"
                        r = run(args.tetfsi, scene(container, ratio, stiffness, dt, args.end, args.damping, args.edge,
                                                   folder), folder, name)
                        s = summary(r, ratio)
                        resolution = f"{r.get('tets', '?')} tets, h = 1/{round(1 / dt)} s"
                        if r["status"] != 0 or s is None:
                            why = r["message"][0][:160] if r["message"] else ""
                            print(f"| {name} | {resolution} | - | {r['wall']:.1f} | {r['peak_mb']:.0f} | "
                                  f"{r['status']} ({why}) | | | | | | | |")
                        else:
                            print(f"| {name} | {resolution} | wall force {100 * s['force_error']:+.2f}% of "
                                  f"(rho_s - rho_f) V g | {r['wall']:.1f} | {r['peak_mb']:.0f} | 0 | "
                                  f"{s['ball']:.1e} | {s['water']:.1e} | {s['penetration']:.1e} | "
                                  f"{s['gap']:.4f} ({s['film']:.4f}) m | {s['rebound']:.3f} m | {s['substeps']} | "
                                  f"{s['cost']:.2f} |")
                        sys.stdout.flush()


if __name__ == "__main__":
    main()
