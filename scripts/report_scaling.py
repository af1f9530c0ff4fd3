#!/usr/bin/python3
"""The scaling section of the speed-against-error report: the coupled step on the flagship geometry
at growing size, with its solvers side by side.

    scripts/report_scaling.py [--tetfsi BUILD/apps/tetfsi] [--scales 0.65 0.40 0.30] [--steps 8]
                              [--compare-steps 4] [--compare bicgstab,umfpack,projection]
                              [--threads 2] [--out DIR] [--work DIR]

For each scale s, data/scenes/smoke_sheets.json (Chentanez et al. 2006, Fig. 1: a smoke jet, two
rubber sheets, eq. 7 every step) with both mesh edge lengths times s, no output files, run twice:

  1. `--steps` steps of 1/60 s as the scene has it: wall time per step (the sum of stats.csv's
     phases, steps 2 on: step 1 builds what later steps reuse), per fluid tet, per phase, the
     process's peak memory (ru_maxrss, meshing included) and per fluid tet;
  2. `--compare-steps` steps with `coupling.compare_solvers` set: every step's system of eq. (7) is
     solved again by BiCGSTAB and UMFPACK, and its fluid block alone by the fluid's pressure solver
     (the fluid-only projection of the same mesh), from the same guess to the same tolerance.
     Ratios are of the means over steps 2 on: the coupled solve (`schur_cg`, the default fast
     path) against the projection, BiCGSTAB and UMFPACK against the fast path.

Writes DIR/scaling.md (the tables, the growth exponents between sizes, and the bars of the scaling
issue with met / not met) and DIR/scaling.csv; prints the tables. Exits 1 if a run fails.
"""

import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import report_output  # noqa: E402

FLAGSHIP = os.path.join(ROOT, "data", "scenes", "smoke_sheets.json")
STEP = 1.0 / 60.0
PHASES = ["remesh", "advect", "solid_assemble", "interface", "solve"]
AUTO_AMG_MOTION_ABOVE_TETS = 500_000  # MeshUpdateOptions::amg_motion_above_tets
BARS = {"us_per_tet": 1.5, "growth": 1.1, "kb_per_tet": 1.0, "coupled_over_projection": 1.5,
        "bicgstab_over_fast": 3.0, "umfpack_over_fast": 10.0}


def scene(scale, steps, compare, motion=None):
    s = json.load(open(FLAGSHIP))
    s["mesh"]["edge_length"] *= scale
    s["mesh"]["edge_length_near_solids"] *= scale
    s["simulation"]["end_time"] = steps * STEP
    s["simulation"]["dt"] = STEP
    s["export"] = {"vtu": False, "surfaces": "none"}
    s.pop("probes", None)
    if compare:
        s.setdefault("coupling", {})["compare_solvers"] = compare
    if motion:
        s.setdefault("coupling", {})["mesh_motion_solver"] = motion
    return s


def run(args, s, folder):
    """Runs scene s into folder; returns (stats rows, wall [s], peak [MB])."""
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    path = os.path.join(folder, "scene.json")
    with open(path, "w") as f:
        json.dump(s, f, indent=1)
    cmd = [args.tetfsi, "run", path, "--out", os.path.join(folder, "out"), "--quiet", "--threads",
           str(args.threads), "--max-tets", "50000000"]
    start = time.monotonic()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    out = p.stdout.read()
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.monotonic() - start
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"report_scaling.py: {' '.join(cmd)} failed:\n{out[-2000:]}")
    rows = list(csv.DictReader(open(os.path.join(folder, "out", "stats.csv"))))
    return rows, wall, usage.ru_maxrss / 1024.0


def mean(rows, key):
    later = [r for r in rows if int(r["step"]) > 1] or rows
    return sum(float(r[key]) for r in later) / len(later)


def step_figures(rows, tets):
    """Mean step over steps 2 on, the steady (median from step 3 on) and the slowest step [s]."""
    r = {}
    for ph in PHASES:
        r["t_" + ph] = mean(rows, "t_" + ph)
    r["step"] = sum(r["t_" + ph] for ph in PHASES)
    r["us_per_tet"] = 1e6 * r["step"] / tets
    # Between remeshes: the median step from step 3 on (step 2 factorizes the mesh motion's
    # stiffened Laplacian, which later steps reuse until the next remesh), and the slowest step.
    sums = [(int(x["step"]), sum(float(x["t_" + ph]) for ph in PHASES)) for x in rows]
    steady = sorted(v for k, v in sums if k > 2) or [v for _, v in sums]
    r["steady_step"] = steady[len(steady) // 2] if len(steady) % 2 else 0.5 * (steady[len(steady) // 2 - 1] + steady[len(steady) // 2])
    r["slowest_step"] = max(v for k, v in sums if k > 1) if len(sums) > 1 else sums[0][1]
    return r


def measure(args, scale, work, last):
    rows, wall, peak = run(args, scene(scale, args.steps, None), os.path.join(work, f"step_{scale}"))
    tets = int(float(rows[-1]["fluid_tets"]))
    r = {"scale": scale, "fluid_tets": tets, "pressure_unknowns": int(float(rows[-1]["pressure_unknowns"])),
         "solid_dofs": int(float(rows[-1]["solid_dofs"])), "steps": len(rows),
         "remeshes": sum(int(float(x["remeshed"])) for x in rows), "wall": wall, "peak_mb": peak}
    r.update(step_figures(rows, tets))
    r["kb_per_tet"] = 1024.0 * peak / tets
    if args.other_motion == "all" or (args.other_motion == "largest" and last):
        # The mesh motion solver `auto` did not pick at this size (coupling/mesh_update.hpp).
        r["default_motion"] = "amg" if tets > AUTO_AMG_MOTION_ABOVE_TETS else "cholesky"
        r["other_motion"] = "cholesky" if r["default_motion"] == "amg" else "amg"
        rows, _, peak = run(args, scene(scale, args.steps, None, r["other_motion"]),
                            os.path.join(work, f"{r['other_motion']}_motion_{scale}"))
        r.update({"other_motion_" + k: v for k, v in step_figures(rows, tets).items()})
        r["other_motion_peak_mb"] = peak
        r["other_motion_kb_per_tet"] = 1024.0 * peak / tets
    if args.compare:
        rows, _, _ = run(args, scene(scale, args.compare_steps, args.compare.split(",")),
                         os.path.join(work, f"compare_{scale}"))
        r["fast_solve"] = mean(rows, "t_solve")
        for name in args.compare.split(","):
            failed = sum(1 for x in rows if float(x[f"compare_{name}_iterations"]) < 0)
            r[f"{name}_solve"] = mean(rows, f"compare_{name}_seconds")
            r[f"{name}_failed"] = failed
    return r


def growth(results, key):
    """Exponent a of key ~ n^a between consecutive sizes and from the first to the last."""
    pairs = list(zip(results, results[1:]))
    if len(results) > 2:
        pairs.append((results[0], results[-1]))
    return [(a["fluid_tets"], b["fluid_tets"],
             math.log(b[key] / a[key]) / math.log(b["fluid_tets"] / a["fluid_tets"])) for a, b in pairs]


def verdict(value, bar, larger_is_better=False):
    ok = value >= bar if larger_is_better else value <= bar
    return "met" if ok else "not met"


def page(args, results, total, load):
    lines = ["# Scaling: the coupled step on the flagship geometry", "",
             "Made by `" + " ".join(["scripts/report_scaling.py"] + sys.argv[1:]).replace(ROOT + os.sep, "") +
             f"` in {total:.0f} s ({report_output.machine(load)}; Release build, `--threads {args.threads}`).", "",
             "`data/scenes/smoke_sheets.json` (coupled smoke jet and two rubber sheets, eq. 7 of Chentanez "
             "et al. 2006 every step, `remesh_when_needed`) with both edge lengths scaled, steps of 1/60 s, no "
             "output. Times are means over steps 2 on (step 1 builds the factorizations and AMG hierarchies "
             "that later steps reuse; up to "
             f"{AUTO_AMG_MOTION_ABOVE_TETS:,} fluid tets step 2 factorizes the mesh motion's stiffened Laplacian, "
             "reused until the next remesh, so with few steps that one factorization weighs on the mean); the "
             "steady step is the "
             "median from step 3 on; peak memory is the whole process's, meshing included.", "",
             "## Step time and memory", "",
             "| scale | fluid tets | pressure unknowns | solid dofs | steps (remeshed) | step [s] | µs per tet | "
             + " | ".join(PHASES) + " | steady step [s] (µs per tet) | slowest step [s] | peak [MB] | kB per tet |",
             "|" + "---|" * (11 + len(PHASES))]
    for r in results:
        lines.append(f"| {r['scale']:g} | {r['fluid_tets']:,} | {r['pressure_unknowns']:,} | {r['solid_dofs']:,} | "
                     f"{r['steps']} ({r['remeshes']}) | {r['step']:.3f} | {r['us_per_tet']:.2f} | "
                     + " | ".join(f"{r['t_' + ph]:.3f}" for ph in PHASES)
                     + f" | {r['steady_step']:.3f} ({1e6 * r['steady_step'] / r['fluid_tets']:.2f}) | "
                     f"{r['slowest_step']:.3f} | {r['peak_mb']:.0f} | {r['kb_per_tet']:.2f} |")
    lines += ["", "Growth of the step time, n^a between sizes: " +
              "; ".join(f"{a:,} → {b:,} tets: a = {e:.2f}" for a, b, e in growth(results, "step")) + ".", ""]
    other = [r for r in results if "other_motion_step" in r]
    if other:
        lines += ["## The mesh motion by the other solver", "",
                  "The same runs with the `coupling.mesh_motion_solver` that `auto` did not pick: `cholesky` (the "
                  "CHOLMOD factorization, made once per mesh at its second step) where `auto` uses `amg` (CG with a "
                  f"BoomerAMG V-cycle from the extrapolated motion; no factor in memory: above "
                  f"{AUTO_AMG_MOTION_ABOVE_TETS:,} fluid tets), and `amg` where it factorizes.", "",
                  "| fluid tets | default (`auto`) | step [s] (µs per tet), default | step [s] (µs per tet), other | "
                  "remesh column, default | remesh column, other | steady step [s], default | steady step [s], other | "
                  "peak [MB] (kB per tet), default | peak [MB] (kB per tet), other |", "|" + "---|" * 10]
        for r in other:
            lines.append(f"| {r['fluid_tets']:,} | `{r['default_motion']}` | {r['step']:.3f} ({r['us_per_tet']:.2f}) | "
                         f"{r['other_motion_step']:.3f} ({r['other_motion_us_per_tet']:.2f}) | {r['t_remesh']:.3f} | "
                         f"{r['other_motion_t_remesh']:.3f} | {r['steady_step']:.3f} | {r['other_motion_steady_step']:.3f} | "
                         f"{r['peak_mb']:.0f} ({r['kb_per_tet']:.2f}) | {r['other_motion_peak_mb']:.0f} "
                         f"({r['other_motion_kb_per_tet']:.2f}) |")
        lines.append("")
    if args.compare:
        names = args.compare.split(",")
        lines += ["## Solvers side by side (the same system each step)", "",
                  "| fluid tets | fast path `schur_cg` [s] | " + " | ".join(f"`{n}` [s]" for n in names) +
                  " | coupled / projection | BiCGSTAB / fast | UMFPACK / fast |",
                  "|" + "---|" * (5 + len(names))]
        for r in results:
            ratio = lambda n, inverse=False: (f"{(r['fast_solve'] / r[n + '_solve'] if inverse else r[n + '_solve'] / r['fast_solve']):.2f}"
                                              if n in names else "n/a")
            cells = [f"{r[n + '_solve']:.3f}" + (f" ({r[n + '_failed']} missed the tolerance)" if r[n + "_failed"] else "")
                     for n in names]
            lines.append(f"| {r['fluid_tets']:,} | {r['fast_solve']:.3f} | " + " | ".join(cells) +
                         f" | {ratio('projection', True)} | {ratio('bicgstab')} | {ratio('umfpack')} |")
        lines.append("")
    last = results[-1]
    lines += ["## Against the bars", "", "| bar | measured | |", "|---|---|---|",
              f"| step ≤ {BARS['us_per_tet']} µs per fluid tet at the largest size | {last['us_per_tet']:.2f} µs "
              f"({last['fluid_tets']:,} tets) | {verdict(last['us_per_tet'], BARS['us_per_tet'])} |"]
    if len(results) > 1:
        e = math.log(last["step"] / results[0]["step"]) / math.log(last["fluid_tets"] / results[0]["fluid_tets"])
        lines.append(f"| growth ≤ n^{BARS['growth']} from the smallest to the largest | n^{e:.2f} | "
                     f"{verdict(e, BARS['growth'])} |")
    lines.append(f"| peak ≤ {BARS['kb_per_tet']} kB per fluid tet at the largest size | {last['kb_per_tet']:.2f} kB | "
                 f"{verdict(last['kb_per_tet'], BARS['kb_per_tet'])} |")
    if args.compare:
        names = args.compare.split(",")
        for n, key, larger, label in [("projection", "coupled_over_projection", False, "coupled solve ≤ 1.5× the projection"),
                                      ("bicgstab", "bicgstab_over_fast", True, "fast path ≥ 3× faster than BiCGSTAB"),
                                      ("umfpack", "umfpack_over_fast", True, "fast path ≥ 10× faster than UMFPACK")]:
            if n not in names:
                continue
            values = [(r["fast_solve"] / r[n + "_solve"]) if n == "projection" else r[n + "_solve"] / r["fast_solve"]
                      for r in results]
            worst = max(values) if not larger else min(values)
            lines.append(f"| {label}, at every size | " + ", ".join(f"{v:.2f}×" for v in values) +
                         f" | {verdict(worst, BARS[key], larger)} |")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tetfsi", default=os.path.join(ROOT, "build", "apps", "tetfsi"))
    ap.add_argument("--scales", type=float, nargs="+", default=[0.65, 0.40, 0.30])
    ap.add_argument("--steps", type=int, default=8)
    ap.add_argument("--compare-steps", type=int, default=4)
    ap.add_argument("--compare", default="projection,bicgstab,umfpack",
                    help="coupling.compare_solvers of the second run ('' for none)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--other-motion", choices=["none", "largest", "all"], default="largest",
                    help="also run these sizes with the coupling.mesh_motion_solver that auto does not pick there")
    ap.add_argument("--out", default=os.path.join("out", "report"))
    ap.add_argument("--work", help="folder for the runs (default: a temporary folder, removed)")
    args = ap.parse_args()
    work = args.work or tempfile.mkdtemp(prefix="tetfsi_scaling_")
    os.makedirs(args.out, exist_ok=True)
    start, load = time.monotonic(), os.getloadavg()[0]
    results = []
    try:
        for k, scale in enumerate(args.scales):
            results.append(measure(args, scale, work, k + 1 == len(args.scales)))
            r = results[-1]
            print(f"scale {scale:g}: {r['fluid_tets']:,} fluid tets, step {r['step']:.3f} s "
                  f"({r['us_per_tet']:.2f} µs per tet), peak {r['peak_mb']:.0f} MB ({r['kb_per_tet']:.2f} kB per tet)"
                  + (f", fast solve {r['fast_solve']:.3f} s, " + ", ".join(
                      f"{n} {r[n + '_solve']:.3f} s" for n in args.compare.split(",")) if args.compare else ""),
                  flush=True)
    finally:
        if not args.work:
            shutil.rmtree(work, ignore_errors=True)
    text = page(args, results, time.monotonic() - start, load)
    with open(os.path.join(args.out, "scaling.md"), "w") as f:
        f.write(text)
    with open(os.path.join(args.out, "scaling.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(dict.fromkeys(k for r in results for k in r)))
        w.writeheader()
        w.writerows(results)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
