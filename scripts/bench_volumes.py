#!/usr/bin/python3
"""Benchmark: what export.volumes "vdb" (OpenVDB frames) adds to a run, through `tetfsi run`.

    scripts/bench_volumes.py --tetfsi build/apps/tetfsi [--scene data/scenes/smoke_sheets_ci.json]
                             [--voxel 0.02 0.01 ...] [--repeat 3] [--out DIR]

Runs the scene (default: the flagship CI scene) with volumes off, with the default voxel size (half
the fluid's mean edge length) and at each --voxel size, and prints one table: case, voxel size [m],
.vdb bytes per frame, output seconds per frame (stats.csv t_output summed over the run / frames
written; the smallest of --repeat runs) and the seconds volumes add to it, wall time and peak memory
of the run.
"""

import argparse
import csv
import json
import os
import re
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def run(tetfsi, scene, out):
    """Runs `scene` into `out`; returns (wall [s], peak RSS [MB])."""
    path = out + ".json"
    with open(path, "w") as f:
        json.dump(scene, f)
    start = time.monotonic()
    p = subprocess.Popen([tetfsi, "run", path, "--out", out, "--quiet"], stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE)
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.monotonic() - start
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"{path}: tetfsi run failed:\n{p.stderr.read().decode()}")
    return wall, usage.ru_maxrss / 1024


def measure(out):
    """(.vdb bytes per frame, output seconds per frame, voxel size [m] or None) of a finished run."""
    log = open(os.path.join(out, "run.log")).read()
    frames = int(re.search(r"output: (\d+) frame\(s\)", log).group(1))
    volumes = int(re.search(r"volumes (\d+)\), \d+ bytes per frame", log).group(1))
    voxel = re.search(r"at a voxel size of ([0-9.e+-]+) m", log)
    t_output = sum(float(r["t_output"]) for r in csv.DictReader(open(os.path.join(out, "stats.csv"))))
    return volumes / frames, t_output / frames, float(voxel.group(1)) if voxel else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tetfsi", required=True)
    ap.add_argument("--scene", default=os.path.join(HERE, "..", "data", "scenes", "smoke_sheets_ci.json"))
    ap.add_argument("--voxel", type=float, nargs="*", default=[0.02, 0.01])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    base = json.load(open(args.scene))
    out_dir = args.out or tempfile.mkdtemp(prefix="bench_volumes_")
    os.makedirs(out_dir, exist_ok=True)
    cases = [("volumes none", None, None), ("vdb, default voxel", "vdb", None)]
    cases += [(f"vdb, voxel {h:g} m", "vdb", h) for h in args.voxel]
    print(f"scene {os.path.basename(args.scene)}, best of {args.repeat} runs, output in {out_dir}")
    print(f"{'case':<22} {'voxel [m]':>10} {'vdb bytes/frame':>16} {'t_output/frame [s]':>19} "
          f"{'added [s]':>10} {'wall [s]':>9} {'peak [MB]':>10}")
    baseline = None
    for i, (name, volumes, h) in enumerate(cases):
        scene = json.loads(json.dumps(base))
        scene.setdefault("export", {})
        if volumes:
            scene["export"]["volumes"] = volumes
        if h:
            scene["export"]["voxel_size"] = h
        best = None
        for r in range(args.repeat):
            out = os.path.join(out_dir, f"case{i}_{r}")
            wall, peak = run(args.tetfsi, scene, out)
            per_frame, t_frame, voxel = measure(out)
            if best is None or t_frame < best[1]:
                best = (per_frame, t_frame, voxel, wall, peak)
        per_frame, t_frame, voxel, wall, peak = best
        if baseline is None:
            baseline = t_frame
        print(f"{name:<22} {voxel if voxel else float('nan'):>10.4g} {per_frame:>16.0f} {t_frame:>19.4f} "
              f"{t_frame - baseline:>10.4f} {wall:>9.2f} {peak:>10.0f}")


if __name__ == "__main__":
    main()
