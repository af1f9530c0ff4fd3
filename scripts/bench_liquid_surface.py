"""Benchmark: the liquid surface export (export.liquid_surface) per frame against a step, and the
volume each frame's surface encloses against the simulated liquid's.

    scripts/bench_liquid_surface.py --tetfsi build/apps/tetfsi [--scenes bowl_drop_ci dam_break]
                                    [--end-time 0.6] [--surface-edge 0.018 ...] [--threads 1] [--out DIR]

Cases: each committed scene of --scenes (data/scenes/NAME.json, its full length or --end-time if
shorter), and for each --surface-edge s data/scenes/dam_break.json without its post (fluid runner)
with `fluid.surface_edge_length` s and `mesh.edge_length` 2 s (0.018 m: about 90k tets), all with
.vtu frames off. Each case runs twice, with the smooth surface (the default) and with "tets" (the
marching-tets surface): the simulation is the same, only the PLYs differ. One row per run: fluid
tets (largest), steps, frames, mean step (the phases of stats.csv), mean and largest output time
per frame (stats.csv t_output on the rows that wrote a frame), the surface's triangles in the last
frame, the largest |V_surface / V_liquid - 1| over the frames (V_surface: the PLY's enclosed volume
by the divergence theorem; V_liquid: the scene's fluid_volume probe at the frame's time), wall time.
"""

import argparse
import csv
import json
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from bench_liquid_steps import run  # noqa: E402
from blender_import import read_ply  # noqa: E402  (numpy, Debian's python3-numpy)


def enclosed_volume(path):
    x, _, t = read_ply(path)
    x = x.astype(np.float64)
    return float(np.einsum("ij,ij->i", x[t[:, 0]], np.cross(x[t[:, 1]], x[t[:, 2]])).sum() / 6)


def volume_gap(out, scene):
    """Largest |V_surface / V_liquid - 1| over the frames, V_liquid from the fluid_volume probe."""
    name = next(p["name"] for p in scene["probes"] if p["kind"] == "fluid_volume")
    probes = [(float(r["time"]), float(r[name])) for r in csv.DictReader(open(os.path.join(out, "probes.csv")))]
    rate = scene["simulation"]["frame_rate"]
    gap = 0.0
    for f in sorted(os.listdir(os.path.join(out, "surfaces"))):
        if f.startswith("liquid_"):
            t = int(f[len("liquid_"):-len(".ply")]) / rate
            v = min(probes, key=lambda p: abs(p[0] - t))[1]
            gap = max(gap, abs(enclosed_volume(os.path.join(out, "surfaces", f)) / v - 1))
    return gap


def summarize(out, scene, wall):
    rows = list(csv.DictReader(open(os.path.join(out, "stats.csv"))))
    phases = [k for k in rows[0] if k.startswith("t_") and k != "t_output"]
    steps = [r for r in rows if int(r["step"]) > 0]
    step = sum(sum(float(r[k]) for k in phases) for r in steps) / len(steps)
    frames = sorted(f for f in os.listdir(os.path.join(out, "surfaces")) if f.startswith("liquid_"))
    outputs = [float(r["t_output"]) for r in rows if float(r["t_output"]) > 0]
    outputs = sorted(outputs, reverse=True)[:len(frames)]  # the rows that wrote a frame
    tets = max(int(float(r.get("fluid_tets", r.get("tets", 0)))) for r in steps)
    _, _, triangles = read_ply(os.path.join(out, "surfaces", frames[-1]))
    return {"tets": tets, "steps": len(steps), "frames": len(frames), "step": step,
            "output": sum(outputs) / len(outputs), "output_max": max(outputs), "triangles": len(triangles),
            "volume": volume_gap(out, scene), "wall": wall}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tetfsi", required=True)
    ap.add_argument("--scenes", nargs="*", default=["bowl_drop_ci", "dam_break"])
    ap.add_argument("--surface-edge", type=float, nargs="*", default=[])
    ap.add_argument("--end-time", type=float, default=0.6)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    scenes = os.path.join(HERE, "..", "data", "scenes")
    cases = [(name, json.load(open(os.path.join(scenes, name + ".json")))) for name in args.scenes]
    for s in args.surface_edge:
        big = json.load(open(os.path.join(scenes, "dam_break.json")))
        big["solids"] = []
        big["probes"] = [p for p in big.get("probes", []) if p["kind"] in ("fluid_volume", "fluid_kinetic_energy")]
        big.pop("coupling", None)
        big["mesh"].pop("edge_length_near_solids", None)
        big["mesh"]["edge_length"] = 2 * s
        big["fluid"]["surface_edge_length"] = s
        cases.append((f"dam_break_s{s:g}", big))
    outdir = args.out or tempfile.mkdtemp(prefix="bench_liquid_surface_")
    os.makedirs(outdir, exist_ok=True)
    print("| case | surface | fluid tets | steps | frames | mean step [s] | output per frame [s] (max) | "
          "triangles | volume gap | wall [s] |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, scene in cases:
        end_time = min(args.end_time, scene["simulation"]["end_time"])
        for kind in ("smooth", "tets"):
            sc = json.loads(json.dumps(scene))
            sc.setdefault("export", {})["vtu"] = False
            sc["export"]["liquid_surface"] = {"type": kind}
            out = os.path.join(outdir, f"{name}_{kind}")
            r = summarize(out, sc, run(args.tetfsi, sc, out, end_time, args.threads)[0])
            print(f"| {name} | {kind} | {r['tets']:,} | {r['steps']} | {r['frames']} | {r['step']:.3f} | "
                  f"{r['output']:.3f} ({r['output_max']:.3f}) | {r['triangles']:,} | {r['volume']:.1e} | "
                  f"{r['wall']:.1f} |", flush=True)


if __name__ == "__main__":
    main()
