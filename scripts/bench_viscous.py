#!/usr/bin/python3
"""Benchmark: viscous flows through `tetfsi run` at three resolutions each, against their references.

    scripts/bench_viscous.py --tetfsi build/apps/tetfsi [--cases cavity settling cost bar] [--threads 2]
                             [--out DIR]

 - cavity: data/scenes/lid_driven_cavity.json (Re = 100) at edge 0.05, 0.025, 0.0167 m to t = 15 s;
   error = the largest |u - u_Ghia| over its 11 centre-line probes (Ghia, Ghia & Shin 1982, Tables
   I and II), relative to the lid speed.
 - settling: data/scenes/stokes_settling.json with the sphere meshed at icosphere level 3, 4, 5
   (edge at the sphere 0.015, 0.0075, 0.004 m) to t = 0.8 s; error = settling speed (the last two
   frames) against Stokes' 2/9 (rho_s - rho_f) g R^2 / mu over Haberman & Sayre's (1958) wall
   factor 1.68 for R / R_cylinder = 0.2.
 - cost: the flagship (data/scenes/smoke_sheets.json, coupled) with its edge lengths times 0.65,
   20 steps of 1/60 s with the viscosity of air (1.8e-5 Pa s, no-slip sheets) and with 0: mean step
   time over steps 6-20, its viscous phase, and their ratio.
 - bar: data/scenes/bar_compare_ci.json (Chentanez et al. 2006, Fig. 6) with viscosity 1e-3, 0.1, 1,
   10 Pa s, run three ways to t = 2 s: simultaneous at 1/30 s, time splitting at 1/30 and 1/120 s;
   verdict (bounded or the time it stopped) and the bar's largest displacement.
Each case prints one table: resolution, tets, error against the reference, wall time per step and
per simulated second, peak memory; and the observed order of the error between resolutions.
"""

import argparse
import csv
import json
import math
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from bench_liquid_steps import run  # noqa: E402  (runs a scene, returns wall time and peak memory)

SCENES = os.path.join(HERE, "..", "data", "scenes")
# Ghia, Ghia & Shin (1982), Re = 100: u on x = 0.5 (Table I) and v on y = 0.5 (Table II), interior points.
GHIA_U = [(0.0547, -0.03717), (0.0625, -0.04192), (0.0703, -0.04775), (0.1016, -0.06434), (0.1719, -0.10150),
          (0.2813, -0.15662), (0.4531, -0.21090), (0.5000, -0.20581), (0.6172, -0.13641), (0.7344, 0.00332),
          (0.8516, 0.23151), (0.9531, 0.68717), (0.9609, 0.73722), (0.9688, 0.78871), (0.9766, 0.84123)]
GHIA_V = [(0.0625, 0.09233), (0.0703, 0.10091), (0.0781, 0.10890), (0.0938, 0.12317), (0.1563, 0.16077),
          (0.2266, 0.17507), (0.2344, 0.17527), (0.5000, 0.05454), (0.8047, -0.24533), (0.8594, -0.22445),
          (0.9063, -0.16914), (0.9453, -0.10313), (0.9531, -0.08864), (0.9609, -0.07391), (0.9688, -0.05906)]
GHIA = {"u_y0_1719": -0.10150, "u_y0_2813": -0.15662, "u_y0_4531": -0.21090, "u_y0_6172": -0.13641,
        "u_y0_8516": 0.23151, "u_y0_9531": 0.68717, "v_x0_0938": 0.12317, "v_x0_2344": 0.17527,
        "v_x0_5000": 0.05454, "v_x0_8047": -0.24533, "v_x0_9063": -0.16914}


def rows(out, name):
    return list(csv.DictReader(open(os.path.join(out, name))))


def step_seconds(out, skip=0):
    """Mean wall time of a step from stats.csv (every t_ column but output) and its viscous part,
    over the steps after the first `skip`."""
    steps = [r for r in rows(out, "stats.csv") if int(r["step"]) > skip]
    phases = [k for k in steps[0] if k.startswith("t_") and k != "t_output"]
    mean = sum(sum(float(r[k]) for k in phases) for r in steps) / len(steps)
    visc = sum(float(r.get("t_viscosity", 0)) for r in steps) / len(steps)
    tets = max(int(float(r["tets"] if "tets" in r else r["fluid_tets"])) for r in steps)
    return mean, visc, tets, len(steps)


def table(title, results):
    print(f"\n{title}\n")
    print("| resolution | tets | error | reference | wall per step | wall per simulated s | peak |")
    print("|---|---|---|---|---|---|---|")
    for r in results:
        print(f"| {r['resolution']} | {r['tets']} | {r['error']:.4f} | {r['reference']} | {r['step']:.3f} s | "
              f"{r['per_second']:.1f} s | {r['peak']:.0f} MB |", flush=True)
    for a, b in zip(results, results[1:]):
        if a["error"] > 0 and b["error"] > 0:
            h = (a["tets"] / b["tets"]) ** (1 / 3)  # edge ratio from the tet counts
            print(f"observed order {a['resolution']} -> {b['resolution']}: {math.log(a['error'] / b['error']) / math.log(1 / h):.2f}")


def fitted_error(vtu, edge):
    """Largest |u - u_Ghia| over Ghia's 30 interior centre-line points, the velocity at each point being
    the volume-weighted least-squares linear fit of the tet velocities (the last frame's cell data)
    whose centroids lie within 1.5 edge lengths of it (second order; a probe reads the one tet's
    constant value, an O(edge) sampling error near the lid)."""
    import numpy as np
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(vtu)
    reader.Update()
    grid = reader.GetOutput()
    centres = vtk.vtkCellCenters()
    centres.SetInputData(grid)
    centres.Update()
    c = vtk_to_numpy(centres.GetOutput().GetPoints().GetData())
    u = vtk_to_numpy(grid.GetCellData().GetArray("velocity"))
    quality = vtk.vtkMeshQuality()
    quality.SetInputData(grid)
    quality.SetTetQualityMeasureToVolume()
    quality.Update()
    volume = np.abs(vtk_to_numpy(quality.GetOutput().GetCellData().GetArray("Quality")))
    z = 0.5 * (c[:, 2].min() + c[:, 2].max())

    def at(x, y, k):
        d = c - np.array([x, y, z])
        near = np.linalg.norm(d[:, :2], axis=1) < 1.5 * edge
        a = np.hstack([np.ones((near.sum(), 1)), d[near]])
        w = np.sqrt(volume[near])[:, None]
        coef = np.linalg.lstsq(a * w, u[near, k] * w[:, 0], rcond=None)[0]
        return coef[0]

    return max([abs(at(0.5, y, 0) - ref) for y, ref in GHIA_U] + [abs(at(x, 0.5, 1) - ref) for x, ref in GHIA_V])


def cavity(args, outdir):
    base = json.load(open(os.path.join(SCENES, "lid_driven_cavity.json")))
    results = []
    for edge in (0.05, 0.025, 0.0167):
        scene = json.loads(json.dumps(base))
        scene["mesh"]["edge_length"] = edge
        scene["simulation"]["end_time"] = 15.0
        out = os.path.join(outdir, f"cavity_{edge:g}")
        wall, peak = run(args.tetfsi, scene, out, 15.0, args.threads)
        last = rows(out, "probes.csv")[-1]
        probe_error = max(abs(float(last[k]) - v) for k, v in GHIA.items())
        frames = sorted(f for f in os.listdir(os.path.join(out, "fluid")) if f.endswith(".vtu"))
        error = fitted_error(os.path.join(out, "fluid", frames[-1]), edge)
        step, _, tets, n = step_seconds(out)
        results.append({"resolution": f"edge {edge:g} m", "tets": tets, "error": error, "step": step,
                        "per_second": wall / 15.0, "peak": peak,
                        "reference": f"Ghia et al. 1982, max over 30 points (the 11 probes: {probe_error:.4f})"})
    table("Lid-driven cavity, Re = 100 (data/scenes/lid_driven_cavity.json, t = 15 s): |u - u_Ghia| / U", results)


def settling(args, outdir):
    base = json.load(open(os.path.join(SCENES, "stokes_settling.json")))
    R, rho_s, rho_f, mu, g = 0.05, 2000.0, 1000.0, 100.0, 9.81
    reference = 2 / 9 * (rho_s - rho_f) * g * R * R / mu / 1.68
    results = []
    for level, edge in ((3, 0.015), (4, 0.0075), (5, 0.004)):
        scene = json.loads(json.dumps(base))
        scene["solids"][0]["geometry"]["subdivisions"] = level
        scene["mesh"]["edge_length_near_solids"] = edge
        scene["mesh"]["facet_distance"] = edge / 8
        out = os.path.join(outdir, f"settling_{level}")
        wall, peak = run(args.tetfsi, scene, out, 0.8, args.threads)
        p = rows(out, "probes.csv")
        v = -(float(p[-1]["centre_z"]) - float(p[-2]["centre_z"])) / (float(p[-1]["time"]) - float(p[-2]["time"]))
        step, _, _, n = step_seconds(out)
        tets = max(int(float(r["fluid_tets"])) for r in rows(out, "stats.csv")[1:])
        results.append({"resolution": f"level {level}, edge {edge:g} m", "tets": tets,
                        "error": abs(v - reference) / reference, "step": step, "per_second": wall / 0.8, "peak": peak,
                        "reference": f"Stokes / 1.68 = {reference:.5f} m/s (measured {v:.5f})"})
    table("Stokes settling (data/scenes/stokes_settling.json, coupled, t = 0.8 s): |v - v_ref| / v_ref", results)


def cost(args, outdir):
    scene = json.load(open(os.path.join(SCENES, "smoke_sheets.json")))
    for key in ("edge_length", "edge_length_near_solids"):
        scene["mesh"][key] *= 0.65
    scene["simulation"]["frame_rate"] = 30
    scene["export"] = {"vtu": False, "surfaces": "none"}
    scene["probes"] = []
    print("\nStep cost with and without viscosity (flagship smoke_sheets.json, edges x 0.65, steps 6-20)\n")
    print("| viscosity | fluid tets | mean step | viscous phase | solve | peak |")
    print("|---|---|---|---|---|---|")
    steps = {}
    for mu in (0.0, 1.8e-5):  # air
        s = json.loads(json.dumps(scene))
        s["fluid"]["viscosity"] = mu
        out = os.path.join(outdir, f"cost_{mu:g}")
        wall, peak = run(args.tetfsi, s, out, 20 / 60, args.threads)
        step, visc, tets, n = step_seconds(out, skip=5)
        solve = sum(float(r["t_solve"]) for r in rows(out, "stats.csv")[6:]) / max(1, n)
        steps[mu] = step
        print(f"| {mu:g} Pa s | {tets} | {step:.3f} s | {visc:.3f} s | {solve:.3f} s | {peak:.0f} MB |", flush=True)
    print(f"viscous step / inviscid step = {steps[1.8e-5] / steps[0.0]:.2f}")


def bar(args, outdir):
    base = json.load(open(os.path.join(SCENES, "bar_compare_ci.json")))
    print("\nBar between opposed jets with a viscous fluid (bar_compare_ci.json, t = 2 s)\n")
    print("| viscosity | simultaneous 1/30 s | splitting 1/30 s | splitting 1/120 s |")
    print("|---|---|---|---|")
    for mu in (1e-3, 0.1, 1.0, 10.0):
        cells = []
        for scheme, h in (("simultaneous", 1 / 30), ("time_splitting", 1 / 30), ("time_splitting", 1 / 120)):
            scene = json.loads(json.dumps(base))
            scene["fluid"]["viscosity"] = mu
            scene["coupling"]["scheme"] = scheme
            scene["simulation"]["dt"] = h
            out = os.path.join(outdir, f"bar_{mu:g}_{scheme}_{round(1 / h)}")
            try:
                run(args.tetfsi, scene, out, 2.0, args.threads)
                stopped = None
            except SystemExit:  # run() exits on a failed run: the bar diverged
                stopped = True
            p = rows(out, "probes.csv")
            x = max(math.sqrt(sum(float(r[f"centre_{c}"]) ** 2 for c in "xyz")) for r in p)
            cells.append(f"stopped at {float(p[-1]['time']):.3f} s" if stopped else f"bounded, max |x| {x:.2g} m")
        print(f"| {mu:g} Pa s | " + " | ".join(cells) + " |", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tetfsi", required=True)
    ap.add_argument("--cases", nargs="*", default=["cavity", "settling", "cost", "bar"])
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    outdir = args.out or tempfile.mkdtemp(prefix="bench_viscous_")
    os.makedirs(outdir, exist_ok=True)
    for case in args.cases:
        {"cavity": cavity, "settling": settling, "cost": cost, "bar": bar}[case](args, outdir)


if __name__ == "__main__":
    main()
