#!/usr/bin/python3
"""Benchmark of the gas-filled spherical membrane (data/scenes/balloon*.json) at several resolutions.

    scripts/bench_balloon.py --tetfsi build/apps/tetfsi [--cases ci,mid,fine] [--out DIR] [--threads 1]

Each case is data/scenes/balloon.json (`fine`) or balloon_ci.json (`ci`), or balloon_ci.json with
grid cell, particle spacing and membrane element size replaced (`mid`), run with `tetfsi run`. The
settled stretch R/R0 (mean of (V / V_m0)^(1/3) over the last quarter of the run, V the
membrane_volume probe) is compared with the roots of the static equilibrium
    2 N / R = p0 (V_g0 / V)^g - p_ext,  N = E h / (1 - nu) (R / R0 - 1),
g = gamma (adiabatic) and g = 1 (isothermal), V_g0 = particles x spacing^3 the gas lattice's
volume and V_m0 the faceted membrane's at t = 0 (tests/apps/test_mpm_balloon.cpp solves the same).
`leaked` counts the gas particles of the last frame that lie outside the membrane by more than
half a particle spacing (along the radius through their nearest membrane node). Prints one table: case, resolution, R/R0, error vs each limit, leaked, CPU and
wall time, peak memory of the run.
"""

import argparse
import csv
import json
import math
import os
import re
import struct
import subprocess
import sys
import time
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = os.path.join(HERE, "..", "data", "scenes")
# case: (scene file, replacements of cell, spacing, element size or None)
CASES = {"ci": ("balloon_ci.json", None), "mid": ("balloon_ci.json", (0.0625, 0.03125, 0.0625)),
         "fine": ("balloon.json", None)}


def stretch(b, g):
    """Root of 2 N / R - (p0 (fill / l^3)^g - p_ext) in l = R / R0 by bisection on [0.5, 3]."""
    lo, hi = 0.5, 3.0
    for _ in range(200):
        l = 0.5 * (lo + hi)
        r = 2 * b["Eh"] / (1 - b["nu"]) * (l - 1) / (b["R0"] * l) - (b["p0"] * (b["fill"] / l**3) ** g - b["p_ext"])
        lo, hi = (lo, l) if r > 0 else (l, hi)
    return 0.5 * (lo + hi)


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def vtu_points(path):
    """Points of a zlib-compressed appended-raw VTU (the format tetfsi writes)."""
    data = open(path, "rb").read()
    start = data.index(b'<AppendedData encoding="raw">')
    base = data.index(b"_", start) + 1
    off = int(re.search(rb'Name="Points" NumberOfComponents="3" format="appended" offset="(\d+)"', data).group(1))
    o = base + off
    nb = struct.unpack_from("<Q", data, o)[0]
    sizes = struct.unpack_from("<%dQ" % (3 + nb), data, o)[3:]
    raw, q = b"", o + 8 * (3 + nb)
    for s in sizes:
        raw += zlib.decompress(data[q:q + s])
        q += s
    v = struct.unpack("<%dd" % (len(raw) // 8), raw)
    return [v[i:i + 3] for i in range(0, len(v), 3)]


def ply_points(path):
    with open(path, "rb") as f:
        n = 0
        while True:
            line = f.readline().decode().strip()
            if line.startswith("element vertex"):
                n = int(line.split()[2])
            if line == "end_header":
                break
        raw = f.read(24 * n)
    return [struct.unpack_from("<3f", raw, 24 * i) for i in range(n)]


def leaked(out, center, spacing):
    """Gas particles of the last frame beyond the membrane by more than half a spacing, measured
    along the radius through the membrane node nearest to each (nodes binned on a 0.1 m lattice)."""
    frames = sorted(os.listdir(os.path.join(out, "particles")))
    last = frames[-1].split("_")[1].split(".")[0]
    rel = lambda p: [p[a] - center[a] for a in range(3)]
    nodes = [rel(p) for p in ply_points(os.path.join(out, "surfaces", "membrane_%s.ply" % last))]
    key = lambda p: tuple(int(math.floor(c / 0.1)) for c in p)
    bins = {}
    for x in nodes:
        bins.setdefault(key(x), []).append(x)
    count = 0
    for p in map(rel, vtu_points(os.path.join(out, "particles", frames[-1]))):
        k = key(p)
        near = [x for i in (-1, 0, 1) for j in (-1, 0, 1) for l in (-1, 0, 1)
                for x in bins.get((k[0] + i, k[1] + j, k[2] + l), [])]
        if not near:  # farther than a bin from every node: inside or far outside
            count += math.hypot(*p) > max(math.hypot(*x) for x in nodes)
            continue
        x = min(near, key=lambda x: math.dist(x, p))
        r = math.hypot(*x)
        count += sum((p[a] - x[a]) * x[a] / r for a in range(3)) > 0.5 * spacing
    return count


def run_case(tetfsi, name, work, threads):
    file, res = CASES[name]
    scene = json.load(open(os.path.join(SCENES, file)))
    m = scene["mpm"]
    if res:
        m["grid"]["cell"], m["bodies"][0]["spacing"], m["membrane"]["element_size"] = res
    path, out = os.path.join(work, name + ".json"), os.path.join(work, name)
    json.dump(scene, open(path, "w"), indent=2)
    start = time.monotonic()
    proc = subprocess.Popen([tetfsi, "run", "-q", path, "--out", out, "--threads", str(threads)],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    log = proc.stdout.read().decode()
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.monotonic() - start
    if status != 0:
        sys.exit("FAILED: %s\n%s" % (" ".join(proc.args), log))
    probes, stats = read_csv(os.path.join(out, "probes.csv")), read_csv(os.path.join(out, "stats.csv"))
    mem, gas = m["membrane"], m["bodies"][0]
    vm0 = float(probes[0]["volume"])
    b = {"R0": mem["shape"]["radius"], "Eh": mem["youngs_modulus"] * mem["thickness"], "nu": mem["poissons_ratio"],
         "p0": gas["pressure"], "p_ext": -mem.get("pressure", 0.0),
         "fill": float(stats[0]["particles"]) * gas["spacing"] ** 3 / vm0}
    t_end = float(probes[-1]["time"])
    window = [(float(r["volume"]) / vm0) ** (1 / 3) for r in probes if float(r["time"]) >= 0.75 * t_end - 1e-12]
    l = sum(window) / len(window)
    l_ad, l_iso = stretch(b, gas["material"]["gamma"]), stretch(b, 1.0)
    return {"case": name, "res": "cell %g, spacing %g, element %g" % (m["grid"]["cell"], gas["spacing"], mem["element_size"]),
            "particles": int(float(stats[0]["particles"])), "l": l, "ad": l_ad, "iso": l_iso,
            "spread": max(window) / min(window) - 1, "leaked": leaked(out, mem["shape"]["center"], gas["spacing"]),
            "cpu": usage.ru_utime + usage.ru_stime, "wall": wall, "mb": usage.ru_maxrss / 1024}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tetfsi", required=True)
    ap.add_argument("--cases", default="ci,mid,fine")
    ap.add_argument("--out", default="bench_balloon")
    ap.add_argument("--threads", type=int, default=1)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = [run_case(args.tetfsi, c, args.out, args.threads) for c in args.cases.split(",")]
    print("| case | resolution | particles | R/R0 (spread) | adiabatic | isothermal | vs adiabatic | vs isothermal "
          "| leaked | CPU s | wall s | peak MB |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print("| %s | %s | %d | %.4f (%.2f%%) | %.4f | %.4f | %+.2f%% | %+.2f%% | %d | %.1f | %.1f | %.0f |" % (
            r["case"], r["res"], r["particles"], r["l"], 100 * r["spread"], r["ad"], r["iso"],
            100 * (r["l"] / r["ad"] - 1), 100 * (r["l"] / r["iso"] - 1), r["leaked"], r["cpu"], r["wall"], r["mb"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
