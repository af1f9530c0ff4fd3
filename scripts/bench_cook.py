#!/usr/bin/env python3
"""Cook's membrane, nonlinear plane strain: hex8 against hex8 with enhanced strains (and CalculiX
C3D8 / C3D8I when `ccx` is on PATH), error in u_y at the loaded edge's midpoint against each law's
converged value, with wall time and peak memory.

The trapezoid (0, 0), (48, 44), (48, 60), (0, 44) mm, 1 mm thick, n x n x 1 hexes; the left edge
clamped, w = 0 on every other node (plane strain), 1 N along y spread uniformly over the 16 mm x
1 mm end face (traction 62.5 kPa), compressible neo-Hookean, mu = 422.5 kPa, nu = 0.3. tetfsi runs
`tetfsi run` (static analysis, `static.load_steps` steps) on a Gmsh .msh file the script writes, with
`model.formulation` "standard" or "enhanced". CalculiX runs the same nodes and hexes (NLGEOM,
*HYPERELASTIC, NEO HOOKE with C10 = mu/2, D1 = 2/K): its law is the isochoric/volumetric split, so
its converged value differs from tetfsi's (Bonet & Wood's law); each code is compared with its own.

The converged value of each code is the Richardson extrapolation of its enhanced element (C3D8I)
on the three finest meshes: u_inf = u_n + (u_n - u_{n/2}) / (2^p - 1), p = log2((u_{n/2} - u_{n/4}) /
(u_n - u_{n/2})). The extrapolation of the standard element is printed beside it as a check.

Usage: scripts/bench_cook.py [--build build] [--divisions 2 4 8 16 32 64] [--steps 10]
"""
import argparse
import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

from make_quarter_ring_hex import write_msh

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MU, NU = 422.5e3, 0.3
E = 2 * MU * (1 + NU)
K = E / (3 * (1 - 2 * NU))
THICKNESS = 1e-3
TRACTION = 1.0 / (16e-3 * THICKNESS)  # 1 N over the end face [Pa]


def mesh(n):
    """Nodes (x, y, z) [m] and hexes (0-based, VTK / Gmsh / CalculiX order) of the n x n x 1 mesh."""
    def tag(i, j, k):
        return i + (n + 1) * (j + (n + 1) * k)
    nodes = []
    for k in range(2):
        for j in range(n + 1):
            for i in range(n + 1):
                s, t = i / n, j / n
                nodes.append((48e-3 * s, 44e-3 * s + t * (44e-3 - 28e-3 * s), THICKNESS * k))
    hexes = []
    for j in range(n):
        for i in range(n):
            bottom = [tag(i, j, 0), tag(i + 1, j, 0), tag(i + 1, j + 1, 0), tag(i, j + 1, 0)]
            hexes.append(bottom + [b + (n + 1) * (n + 1) for b in bottom])
    return nodes, hexes


def scene(msh, formulation, steps):
    eps = 1e-9
    return {
        "description": "Cook's membrane, nonlinear plane strain (scripts/bench_cook.py)",
        "simulation": {"end_time": 1.0, "dt": 1.0, "gravity": [0, 0, 0]},
        "solids": [{
            "name": "cook",
            "geometry": {"type": "volume_mesh", "file": msh},
            "model": {"type": "hex8", "analysis": "static", "formulation": formulation},
            "material": {"density": 1000, "youngs_modulus": E, "poissons_ratio": NU, "constitutive": "neohookean"},
            "boundary_conditions": [
                {"type": "fixed", "box": {"lo": [-1, -1, -1], "hi": [eps, 1, 1]}},
                {"type": "fixed", "components": "z", "box": {"lo": [1e-6, -1, -1], "hi": [1, 1, 1]}},
                {"type": "traction", "value": [0, TRACTION, 0], "box": {"lo": [48e-3 - eps, -1, -1], "hi": [1, 1, 1]}},
            ],
            "static": {"load_steps": steps},
        }],
        "probes": [{"name": "tip", "kind": "point_displacement", "solid": "cook", "point": [48e-3, 52e-3, 0]}],
    }


def timed(cmd, folder, name, env=None):
    """Runs cmd; returns (wall seconds, peak resident MB)."""
    mem = os.path.join(folder, name + ".time")
    subprocess.run(["/usr/bin/time", "-f", "%e %M", "-o", mem] + cmd, check=True, cwd=folder, env=env,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(mem) as f:
        wall, kb = f.read().split()[-2:]
    return float(wall), float(kb) / 1024


def run_tetfsi(binary, n, formulation, steps, folder):
    name = f"{formulation}{n}"
    msh = os.path.join(folder, f"cook{n}.msh")
    if not os.path.exists(msh):
        nodes, hexes = mesh(n)
        write_msh(msh, nodes, [[v + 1 for v in h] for h in hexes])
    path = os.path.join(folder, name + ".json")
    with open(path, "w") as f:
        json.dump(scene(msh, formulation, steps), f)
    out = os.path.join(folder, name)
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    wall, mb = timed([binary, "run", path, "--out", out, "--quiet", "--threads", "1"], folder, name, env)
    with open(os.path.join(out, "probes.csv")) as f:
        rows = list(csv.DictReader(f))
    return float(rows[-1]["tip_y"]), wall, mb


def run_ccx(n, element, steps, folder):
    name = f"{element}_{n}"
    nodes, hexes = mesh(n)
    probe = [i for i, (x, y, z) in enumerate(nodes) if abs(x - 48e-3) < 1e-12 and abs(y - 52e-3) < 1e-12]
    end = [i for i, (x, y, z) in enumerate(nodes) if abs(x - 48e-3) < 1e-12]
    with open(os.path.join(folder, name + ".inp"), "w") as f:
        f.write("*NODE\n" + "".join(f"{i + 1}, {x:.12g}, {y:.12g}, {z:.12g}\n" for i, (x, y, z) in enumerate(nodes)))
        f.write(f"*ELEMENT, TYPE={element}, ELSET=EALL\n")
        f.write("".join(f"{q + 1}, " + ", ".join(str(v + 1) for v in h) + "\n" for q, h in enumerate(hexes)))
        sets = {"FIX": [i for i, p in enumerate(nodes) if p[0] < 1e-12],
                "REST": [i for i, p in enumerate(nodes) if p[0] >= 1e-12], "PROBE": probe}
        for s, ids in sets.items():
            f.write(f"*NSET, NSET={s}\n" + "".join(f"{i + 1},\n" for i in ids))
        f.write("*BOUNDARY\nFIX, 1, 3\nREST, 3, 3\n")
        f.write(f"*MATERIAL, NAME=RUBBER\n*HYPERELASTIC, NEO HOOKE\n{MU / 2:.10g}, {2 / K:.10g}\n")  # ccx reads up to 20 characters a field
        f.write("*SOLID SECTION, ELSET=EALL, MATERIAL=RUBBER\n")
        f.write(f"*STEP, NLGEOM, INC=1000\n*STATIC\n{1 / steps}, 1.0\n*CLOAD\n")
        for i in end:  # uniform traction: a quarter of each end quad's force on each of its corners
            y = nodes[i][1]
            share = 1.0 if abs(y - 44e-3) < 1e-12 or abs(y - 60e-3) < 1e-12 else 2.0
            f.write(f"{i + 1}, 2, {share / (4 * n):.12g}\n")
        f.write("*NODE PRINT, NSET=PROBE\nU\n*END STEP\n")
    env = dict(os.environ, OMP_NUM_THREADS="1", CCX_NPROC_STIFFNESS="1", CCX_NPROC_EQUATION_SOLVER="1")
    wall, mb = timed(["ccx", "-i", name], folder, name, env)
    with open(os.path.join(folder, name + ".dat")) as f:
        text = f.read()
    block = text.split("displacements (vx,vy,vz)")[-1]
    uy = [float(m.group(3)) for m in re.finditer(r"^\s*(\d+)\s+(\S+)\s+(\S+)\s+(\S+)", block, re.M)]
    return sum(uy) / len(uy), wall, mb


def richardson(values):
    """Extrapolation from the last three values at ratio 2: (u_inf, p)."""
    a, b, c = values[-3:]
    p = math.log2((b - a) / (c - b))
    return c + (c - b) / (2 ** p - 1), p


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--divisions", type=int, nargs="+", default=[2, 4, 8, 16, 32, 64])
    ap.add_argument("--steps", type=int, default=10)
    args = ap.parse_args()
    binary = os.path.join(args.build, "apps/tetfsi")
    cases = [("tetfsi", "hex8", "standard"), ("tetfsi", "hex8 enhanced", "enhanced")]
    if shutil.which("ccx"):
        cases += [("ccx", "CalculiX C3D8", "C3D8"), ("ccx", "CalculiX C3D8I", "C3D8I")]
    else:
        print("CalculiX (ccx) is not installed: its rows are left out.")
    results = {}
    with tempfile.TemporaryDirectory() as folder:
        for code, label, kind in cases:
            for n in args.divisions:
                r = (run_tetfsi(binary, n, kind, args.steps, folder) if code == "tetfsi"
                     else run_ccx(n, kind, args.steps, folder))
                results[(label, n)] = r
                print(f"  {label} {n}x{n}: u_y {1e3 * r[0]:.5f} mm, {r[1]:.2f} s, {r[2]:.0f} MB", file=sys.stderr)
    converged = {}
    for code in ("tetfsi", "ccx"):
        labels = [c[1] for c in cases if c[0] == code]
        if not labels:
            continue
        ext = {l: richardson([results[(l, n)][0] for n in args.divisions]) for l in labels}
        converged[code] = ext[labels[-1]][0]
        for l in labels:
            print(f"{l}: Richardson on {args.divisions[-3:]}: u_y -> {1e3 * ext[l][0]:.4f} mm (order {ext[l][1]:.2f})")
    print("| case | resolution | u_y [mm] | error vs converged | wall time [s] | peak memory [MB] |")
    print("|---|---|---|---|---|---|")
    for code, label, _ in cases:
        for n in args.divisions:
            uy, wall, mb = results[(label, n)]
            err = uy / converged[code] - 1
            print(f"| {label} | {n}x{n}x1 | {1e3 * uy:.4f} | {100 * err:+.3f}% | {wall:.2f} | {mb:.0f} |")


if __name__ == "__main__":
    main()
