#!/usr/bin/env python3
"""The sloshing tank (data/scenes/sloshing_tank.json) at several edge lengths and time steps:
frequency error against linear theory, amplitude decay per period, and whether the wave energy
ever grows (fluid/README.md, "Walls and handedness").

  scripts/bench_sloshing.py --tetfsi build/apps/tetfsi [--edges 0.04 0.02 0.0133] [--steps 40 80]
                            [--periods 20] [--work DIR]

Each run writes the liquid PLY every 1/40 s. The first mode's amplitude A(t) is fitted to the
free-surface vertices of each frame (the PLY's triangles not lying in a wall plane):
A = sum (y - H) cos(k x) / sum cos^2(k x). The period is twice the mean time between zero
crossings of A, the decay per period comes from a log-linear fit of the extrema |A| (each placed by
a parabola through three frames), and the wave energy is kinetic + gravitational - that of the same
liquid at rest (stats.csv), reported as its largest value in each period over the start's.
"""
import argparse
import csv
import json
import math
import os
import struct
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
L, W, H, A0, G, RHO = 0.8, 0.1, 0.3, 0.005, 9.81, 1000.0
K = math.pi / L
F_THEORY = math.sqrt(G * K * math.tanh(K * H)) / (2 * math.pi)


def read_ply(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().split("\n")
    nv = int([l for l in header if l.startswith("element vertex")][0].split()[2])
    nf = int([l for l in header if l.startswith("element face")][0].split()[2])
    floats = len([l for l in header if l.startswith("property float")])
    vertices = [struct.unpack_from("<3f", data, end + 4 * floats * i) for i in range(nv)]
    offset, faces = end + 4 * floats * nv, []
    for _ in range(nf):
        n = data[offset]
        faces.append(struct.unpack_from("<%di" % n, data, offset + 1))
        offset += 1 + 4 * n
    return vertices, faces


def amplitude(vertices, faces, eps=1e-5):
    walls = [lambda p: abs(p[0]) < eps, lambda p: abs(p[0] - L) < eps, lambda p: abs(p[1]) < eps,
             lambda p: abs(p[2]) < eps, lambda p: abs(p[2] - W) < eps]
    free = set()
    for f in faces:
        if not any(all(w(vertices[i]) for i in f) for w in walls):
            free.update(f)
    num = sum((vertices[i][1] - H) * math.cos(K * vertices[i][0]) for i in free)
    den = sum(math.cos(K * vertices[i][0]) ** 2 for i in free)
    return num / den


def analyse(out, frame_dt):
    frames = sorted(f for f in os.listdir(os.path.join(out, "surfaces")) if f.endswith(".ply"))
    a = [amplitude(*read_ply(os.path.join(out, "surfaces", f))) for f in frames]
    t = [i * frame_dt for i in range(len(a))]
    zeros = [t[i - 1] + frame_dt * a[i - 1] / (a[i - 1] - a[i]) for i in range(1, len(a)) if a[i - 1] * a[i] < 0]
    period = 2 * (zeros[-1] - zeros[0]) / (len(zeros) - 1)
    extrema = []
    for i in range(1, len(a) - 1):
        if (a[i] - a[i - 1]) * (a[i + 1] - a[i]) < 0:
            c, b = (a[i + 1] - 2 * a[i] + a[i - 1]) / 2, (a[i + 1] - a[i - 1]) / 2
            extrema.append((t[i] - b / (2 * c) * frame_dt, abs(a[i] - b * b / (4 * c))))
    n = len(extrema)
    sx, sy = sum(e[0] for e in extrema), sum(math.log(e[1]) for e in extrema)
    sxx, sxy = sum(e[0] ** 2 for e in extrema), sum(e[0] * math.log(e[1]) for e in extrema)
    slope = (n * sxy - sx * sy) / (n * sxx - sx * sx)
    rows = list(csv.DictReader(open(os.path.join(out, "stats.csv"))))
    volume = float(rows[0]["liquid_volume"])
    rest = RHO * G * volume * volume / (2 * W * L)
    e0 = 0.25 * RHO * G * A0 * A0 * L * W
    energy = [(float(r["time"]), float(r["kinetic_energy"]) + float(r["gravity_potential"]) - rest) for r in rows]
    per_period = []
    for p in range(int(energy[-1][0] / period)):
        per_period.append(max(e for tt, e in energy if p * period <= tt < (p + 1) * period) / e0)
    return {"frequency_error": (1 / period) / F_THEORY - 1, "decay": 1 - math.exp(slope * period),
            "energy": per_period, "grows": any(b > a for a, b in zip(per_period, per_period[1:]))}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tetfsi", required=True)
    ap.add_argument("--edges", type=float, nargs="+", default=[0.04, 0.02, 0.0133])
    ap.add_argument("--steps", type=int, nargs="+", default=[40, 80], help="steps per second")
    ap.add_argument("--periods", type=float, default=20)
    ap.add_argument("--work", default="sloshing_runs")
    args = ap.parse_args()
    base = json.load(open(os.path.join(ROOT, "data", "scenes", "sloshing_tank.json")))
    base["fluid"]["regions"][0]["file"] = os.path.join(ROOT, "data", "scenes", "meshes", "sloshing_liquid.obj")
    os.makedirs(args.work, exist_ok=True)
    print("| edge | tets | h | frequency error | amplitude decay per period | largest wave energy per period "
          "(first, last; any rise) | wall |")
    print("|---|---|---|---|---|---|---|")
    for edge in args.edges:
        for steps in args.steps:
            scene = json.loads(json.dumps(base))
            scene["mesh"]["edge_length"] = edge
            scene["simulation"]["dt"] = 1.0 / steps
            scene["simulation"]["end_time"] = round(args.periods / F_THEORY, 4)
            name = "edge%g_h1_%d" % (edge, steps)
            path = os.path.join(args.work, name + ".json")
            json.dump(scene, open(path, "w"), indent=1)
            out = os.path.join(args.work, name)
            start = time.time()
            run = subprocess.run([args.tetfsi, "run", path, "--out", out, "--threads", "1", "--quiet"],
                                 capture_output=True, text=True)
            wall = time.time() - start
            if run.returncode != 0:
                print("| %g | - | 1/%d | run failed (exit %d): %s |" % (edge, steps, run.returncode,
                                                                       run.stdout.strip()[-200:]))
                continue
            tets = open(os.path.join(out, "run.log")).read().split("fluid runner: liquid fluid, ")[1].split(" tets")[0]
            r = analyse(out, 1.0 / scene["simulation"]["frame_rate"])
            print("| %g m | %s | 1/%d s | %+.2f%% | %.1f%% | %.3f, %.3f; %s | %.0f s |" % (
                edge, tets, steps, 100 * r["frequency_error"], 100 * r["decay"], r["energy"][0], r["energy"][-1],
                "rises" if r["grows"] else "never", wall))
            sys.stdout.flush()


if __name__ == "__main__":
    main()
