#!/usr/bin/python3
"""Benchmark: strong scaling of `tetfsi run` over MPI processes (parallel/, PETSc) on one machine.

    scripts/bench_scaling.py --tetfsi build/apps/tetfsi [--cases flagship,pipe] [--scales 0.65 0.42]
                             [--cores 2] [--out DIR]

Cases (each scaled by the --scales factors on its edge lengths):
  flagship  data/scenes/smoke_sheets.json (coupled smoke and two sheets, eq. 7), 6 steps of 1/60 s;
  pipe      data/scenes/pipe_flow.json (fluid runner, liquid; edge 0.02 m x scale), 6 steps of 0.02 s.
Each size runs with no output (export.vtu false, no surfaces) in four set-ups on --cores cores:
  hypre    1 process  x cores threads, fluid.solver.type "amg" (the shared-memory path);
  petsc 1  1 process  x cores threads, "petsc";
  petsc N  cores processes x 1 thread (`mpirun -n cores`), "petsc";
  petsc 1t 1 process  x 1 thread, "petsc" (the base of the solve's strong scaling).
It prints one row per run: case, fluid tets, set-up, mean wall time per step (steps 2-6, the sum of
stats.csv's phases) and its solve phase, solver iterations, speed-up of the step and of the solve
against `petsc 1t`, wall time of the whole run, peak memory of the largest process, and the
largest probe or energy difference from the hypre run (relative to the column's largest value).
"""

import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
MPIRUN = ["mpirun", "--oversubscribe", "--bind-to", "none"]
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def scene_of(case, scale):
    if case == "flagship":
        s = json.load(open(os.path.join(ROOT, "data/scenes/smoke_sheets.json")))
        s["mesh"]["edge_length"] *= scale
        s["mesh"]["edge_length_near_solids"] *= scale
        s["simulation"]["end_time"] = 0.1
    elif case == "pipe":
        s = json.load(open(os.path.join(ROOT, "data/scenes/pipe_flow.json")))
        s["mesh"]["edge_length"] = 0.02 * scale
        s["simulation"]["end_time"] = 0.12
    else:
        sys.exit(f"unknown case {case}")
    s["export"] = {"vtu": False, "surfaces": "none"}
    return s


def run(tetfsi, scene, out, processes, threads):
    """Runs `scene` into `out`; returns (wall [s], peak RSS of the largest process [MB])."""
    path = out + ".json"
    with open(path, "w") as f:
        json.dump(scene, f)
    command = ([*MPIRUN, "-n", str(processes)] if processes > 1 else []) + [
        tetfsi, "run", path, "--out", out, "--quiet", "--threads", str(threads), "--max-tets", "20000000"]
    start = time.monotonic()
    p = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=ENV)
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.monotonic() - start
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"{path}: tetfsi run failed:\n{p.stderr.read().decode()}")
    return wall, usage.ru_maxrss / 1024


def read(path):
    return list(csv.DictReader(open(path)))


def summarize(out):
    rows = read(os.path.join(out, "stats.csv"))
    steps = [r for r in rows if int(r["step"]) > 1]
    phases = [k for k in rows[0] if k.startswith("t_") and k != "t_output"]
    mean = lambda key: sum(float(r[key]) for r in steps) / len(steps)
    its = "iterations" if "iterations" in rows[0] else "solver_iterations"
    tets = "tets" if "tets" in rows[0] else "fluid_tets"
    return {"tets": int(float(rows[-1][tets])), "step": sum(mean(k) for k in phases), "solve": mean("t_solve"),
            "its": "/".join(r[its] for r in steps)}


def difference(a, b):
    """Largest |a - b| over the runs' probes.csv (or stats.csv energies), relative per column."""
    name = "probes.csv" if os.path.exists(os.path.join(a, "probes.csv")) else "stats.csv"
    ra, rb = read(os.path.join(a, name)), read(os.path.join(b, name))
    columns = [k for k in ra[0] if k != "time"] if name == "probes.csv" else \
        [k for k in ra[0] if k in ("fluid_kinetic", "solid_kinetic", "kinetic_energy", "total_energy")]
    worst = 0.0
    for c in columns:
        size = max(abs(float(r[c])) for r in ra if r[c] != "")
        if size > 0:
            worst = max(worst, max(abs(float(x[c]) - float(y[c])) for x, y in zip(ra, rb) if x[c] != "") / size)
    return worst


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tetfsi", default=os.path.join(ROOT, "build/apps/tetfsi"))
    ap.add_argument("--cases", default="flagship,pipe")
    ap.add_argument("--scales", type=float, nargs="+", default=[0.65, 0.42])
    ap.add_argument("--cores", type=int, default=2)
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    work = a.out or tempfile.mkdtemp(prefix="tetfsi_scaling_")
    os.makedirs(work, exist_ok=True)
    setups = [("hypre", "amg", 1, a.cores), ("petsc 1", "petsc", 1, a.cores),
              (f"petsc {a.cores}", "petsc", a.cores, 1), ("petsc 1t", "petsc", 1, 1)]
    print("| case | fluid tets | set-up | step [s] | solve [s] | iterations | step speed-up | solve speed-up "
          "| run wall [s] | peak per process [MB] | probe difference |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for case in a.cases.split(","):
        for scale in a.scales:
            results = []
            for label, solver, processes, threads in setups:
                s = scene_of(case, scale)
                s["fluid"].setdefault("solver", {})["type"] = solver
                out = os.path.join(work, f"{case}_{scale}_{solver}_{processes}x{threads}")
                wall, rss = run(a.tetfsi, s, out, processes, threads)
                results.append((label, out, wall, rss, summarize(out)))
            base = results[-1][4]
            for label, out, wall, rss, r in results:
                print(f"| {case} | {r['tets']:,} | {label} | {r['step']:.3f} | {r['solve']:.3f} | {r['its']} | "
                      f"{base['step'] / r['step']:.2f} | {base['solve'] / r['solve']:.2f} | {wall:.1f} | {rss:.0f} | "
                      f"{difference(results[0][1], out):.1e} |", flush=True)


if __name__ == "__main__":
    main()
