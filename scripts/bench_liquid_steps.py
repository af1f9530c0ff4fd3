#!/usr/bin/python3
"""Benchmark: cost of a free-surface step against mesh size, by phase, through `tetfsi run`.

    scripts/bench_liquid_steps.py --tetfsi build/apps/tetfsi [--surface-edge 0.03 0.018 0.011]
                                  [--end-time 0.15] [--threads 1] [--out DIR]

The case is data/scenes/dam_break.json without its post (the fluid runner: liquid only, surface
refinement on), `fluid.surface_edge_length` s and `mesh.edge_length` 2 s for each s given. For each
run it prints one row: surface edge, fluid tets (largest over the run), steps (of which remeshed),
mean wall time per step and its phases from stats.csv (remesh; surface tracking; advect; forces +
assemble + solve), the largest |volume drift|, wall time and peak memory of the whole run
(meshing included). Last, the growth exponent of the mean step between consecutive sizes,
log(t2/t1) / log(n2/n1).
"""

import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def run(tetfsi, scene, out, end_time, threads):
    """Runs `scene` into `out`; returns (wall [s], peak RSS [MB])."""
    path = out + ".json"
    with open(path, "w") as f:
        json.dump(scene, f)
    start = time.monotonic()
    p = subprocess.Popen([tetfsi, "run", path, "--out", out, "--quiet", "--end-time", str(end_time),
                          "--threads", str(threads)], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.monotonic() - start
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"{path}: tetfsi run failed:\n{p.stderr.read().decode()}")
    return wall, usage.ru_maxrss / 1024


def summarize(out):
    rows = list(csv.DictReader(open(os.path.join(out, "stats.csv"))))
    steps = [r for r in rows if int(r["step"]) > 0]
    mean = lambda key: sum(float(r[key]) for r in steps) / len(steps)
    solve = sum(float(r["t_forces"]) + float(r["t_assemble"]) + float(r["t_solve"]) for r in steps) / len(steps)
    phases = ["t_remesh", "t_surface", "t_advect", "t_forces", "t_assemble", "t_solve"]
    step = sum(sum(float(r[k]) for k in phases) for r in steps) / len(steps)
    return {
        "tets": max(int(float(r["tets"])) for r in steps),
        "steps": len(steps),
        "remeshed": sum(int(float(r["remeshed"])) for r in steps),
        "step": step,
        "remesh": mean("t_remesh"),
        "surface": mean("t_surface"),
        "advect": mean("t_advect"),
        "solve": solve,
        "drift": max(abs(float(r["volume_drift"])) for r in steps),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tetfsi", required=True)
    ap.add_argument("--scene", default=os.path.join(HERE, "..", "data", "scenes", "dam_break.json"))
    ap.add_argument("--surface-edge", type=float, nargs="*", default=[0.03, 0.018, 0.011])
    ap.add_argument("--end-time", type=float, default=0.15)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    base = json.load(open(args.scene))
    base["solids"] = []
    base["probes"] = [p for p in base.get("probes", []) if p["kind"] in ("fluid_volume", "fluid_kinetic_energy")]
    base.pop("coupling", None)
    base["mesh"].pop("edge_length_near_solids", None)
    # The simulation's own surface: the smooth one for renderers would add its cost to wall and peak
    # (scripts/bench_liquid_surface.py measures that).
    base.setdefault("export", {})["liquid_surface"] = {"type": "tets"}
    outdir = args.out or tempfile.mkdtemp(prefix="bench_liquid_")
    os.makedirs(outdir, exist_ok=True)
    print("| surface edge | fluid tets (max) | steps (remeshed) | mean step | remesh | surface | advect | "
          "forces + assemble + solve | max volume drift | wall | peak |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    results = []
    for s in args.surface_edge:
        scene = json.loads(json.dumps(base))
        scene["fluid"]["surface_edge_length"] = s
        scene["mesh"]["edge_length"] = 2 * s
        out = os.path.join(outdir, f"edge_{s:g}")
        wall, peak = run(args.tetfsi, scene, out, args.end_time, args.threads)
        r = summarize(out)
        results.append(r)
        print(f"| {s:g} m | {r['tets']} | {r['steps']} ({r['remeshed']}) | {r['step']:.3f} s | {r['remesh']:.3f} s | "
              f"{r['surface']:.3f} s | {r['advect']:.3f} s | {r['solve']:.3f} s | {r['drift']:.2e} | {wall:.1f} s | "
              f"{peak:.0f} MB |", flush=True)
    for a, b in zip(results, results[1:]):
        print(f"growth {a['tets']} -> {b['tets']} tets: mean step as n^{math.log(b['step'] / a['step']) / math.log(b['tets'] / a['tets']):.2f}")


if __name__ == "__main__":
    main()
