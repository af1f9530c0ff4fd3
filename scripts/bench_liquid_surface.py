"""Benchmark: the cost of the liquid surface export (export.liquid_surface) per frame, against a step.

    scripts/bench_liquid_surface.py --tetfsi build/apps/tetfsi [--surface-edge 0.018] [--end-time 0.1]
                                    [--threads 1] [--out DIR]

Cases: data/scenes/dam_break_ci.json as committed (CI size, coupled), and data/scenes/dam_break.json
without its post (fluid runner) with `fluid.surface_edge_length` s and `mesh.edge_length` 2 s for
each s given (0.018 m: about 90k tets), both with .vtu frames off. Each case runs twice, with the
smooth surface (the default) and with "tets" (the marching-tets surface). One row per run: fluid
tets (largest), steps, frames, mean step (the phases of stats.csv), mean and largest output time
per frame (stats.csv t_output on the rows that wrote a frame), the surface's triangles in the last
frame, the largest relative gap between the enclosed volume and the liquid's (run.log), wall time.
"""

import argparse
import csv
import json
import os
import re
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from bench_liquid_steps import run  # noqa: E402
from blender_import import read_ply  # noqa: E402  (numpy, Debian's python3-numpy)


def summarize(out, wall):
    rows = list(csv.DictReader(open(os.path.join(out, "stats.csv"))))
    phases = [k for k in rows[0] if k.startswith("t_") and k != "t_output"]
    steps = [r for r in rows if int(r["step"]) > 0]
    step = sum(sum(float(r[k]) for k in phases) for r in steps) / len(steps)
    frames = sorted(f for f in os.listdir(os.path.join(out, "surfaces")) if f.startswith("liquid_"))
    outputs = [float(r["t_output"]) for r in rows if float(r["t_output"]) > 0]
    outputs = sorted(outputs, reverse=True)[:len(frames)]  # the rows that wrote a frame
    tets = max(int(float(r.get("tets", r.get("fluid_tets", 0)))) for r in steps)
    _, _, triangles = read_ply(os.path.join(out, "surfaces", frames[-1]))
    log = open(os.path.join(out, "run.log")).read()
    m = re.search(r"enclosed volume within ([0-9.e+-]+) of the liquid's", log)
    return {"tets": tets, "steps": len(steps), "frames": len(frames), "step": step,
            "output": sum(outputs) / len(outputs), "output_max": max(outputs), "triangles": len(triangles),
            "volume": m.group(1) if m else "-", "wall": wall}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tetfsi", required=True)
    ap.add_argument("--surface-edge", type=float, nargs="*", default=[0.018])
    ap.add_argument("--end-time", type=float, default=0.1)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    scenes = os.path.join(HERE, "..", "data", "scenes")
    cases = []
    ci = json.load(open(os.path.join(scenes, "dam_break_ci.json")))
    cases.append(("dam_break_ci", ci))
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
        for kind in ("smooth", "tets"):
            sc = json.loads(json.dumps(scene))
            sc.setdefault("export", {})["vtu"] = False
            sc["export"]["liquid_surface"] = {"type": kind}
            out = os.path.join(outdir, f"{name}_{kind}")
            r = summarize(out, run(args.tetfsi, sc, out, args.end_time, args.threads)[0])
            print(f"| {name} | {kind} | {r['tets']:,} | {r['steps']} | {r['frames']} | {r['step']:.3f} | "
                  f"{r['output']:.3f} ({r['output_max']:.3f}) | {r['triangles']:,} | {r['volume']} | {r['wall']:.1f} |",
                  flush=True)


if __name__ == "__main__":
    main()
