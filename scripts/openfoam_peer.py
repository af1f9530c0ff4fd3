#!/usr/bin/python3
"""OpenFOAM's interFoam as a peer of tetfsi on the sloshing tank and the dam break.

    scripts/openfoam_peer.py sloshing|dam_break --cells N --work DIR [--json]

Writes a 2D case (one cell thick, `empty` front and back) for OpenFOAM's interFoam (volume of
fluid, MULES), meshes it with blockMesh, sets the liquid (the sloshing tank's cosine surface is
written into 0/alpha.water from the cell geometry, the dam break's column by setFields), runs
interFoam on one core and reads its probes. N is the resolution: cells along the tank's length (sloshing) or
along the column's side a (dam break). Prints the cells, the error against the reference (the same
measures as tetfsi's, scripts/liquid_measures.py), the wall time of blockMesh + setFields +
interFoam and the peak memory; with --json one JSON object.

Sloshing: tank L = 0.8 m long, 0.44 m high, still depth H = 0.3 m, first mode started at rest with a
surface 5 mm cos(pi x / L); water and air with nu = 1e-9 m^2/s (as close to inviscid as interFoam
goes), no surface tension, slip walls, open top; 4.5 s (4 periods). Reference: linear theory
f = sqrt(g k tanh kH) / (2 pi) = 0.89825 Hz, no damping.
Dam break: Martin & Moyce (1952) square column a = 2.25 in = 0.05715 m against the left wall of a
channel 5 a long and 2 a high (open top), water (nu 1e-6 m^2/s) and air (nu 1.48e-5), surface
tension 0.07 N/m, no-slip walls, until tau = t sqrt(g/a) = 3.5. Reference: their surge front and
column height tables.

Needs OpenFOAM (Debian's `openfoam` package: blockMesh, setFields and interFoam on the PATH);
`available()` says whether it is there. Debian 12's OpenFOAM v1912 needs no environment script.
"""

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import liquid_measures as lm  # noqa: E402

TOOLS = ("blockMesh", "setFields", "interFoam")

SLOSH = {"length": 0.8, "height": 0.44, "depth": 0.3, "amplitude": 0.005, "end_time": 4.5}
DAM = {"a": 0.05715, "length": 5.0, "height": 2.0, "end_tau": 3.5}


def available():
    """True if blockMesh, setFields and interFoam are on the PATH."""
    return all(shutil.which(t) for t in TOOLS)


def environment():
    """The environment the tools run in: OpenFOAM finds its etc/controlDict under WM_PROJECT_DIR,
    which Debian's package leaves unset (its files are in /usr/share/openfoam)."""
    env = dict(os.environ)
    if not os.path.isfile(os.path.join(env.get("WM_PROJECT_DIR", ""), "etc", "controlDict")):
        env["WM_PROJECT_DIR"] = "/usr/share/openfoam"
    return env


def version():
    """OpenFOAM's version as interFoam prints it (e.g. 'v1912'), or 'unknown'."""
    try:
        out = subprocess.run(["interFoam", "-help"], capture_output=True, text=True, timeout=60,
                             env=environment()).stdout
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    for line in out.splitlines():
        if "Using: OpenFOAM-" in line:
            return line.split("Using: OpenFOAM-")[1].split(" - ")[0].strip(" ()") or "unknown"
    return "unknown"


def foam_file(path, cls, obj, body):
    """Writes an OpenFOAM dictionary file: the FoamFile header, then `body`."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(f"FoamFile\n{{\n    version 2.0;\n    format ascii;\n    class {cls};\n    object {obj};\n}}\n\n")
        f.write(body)


def block_mesh(lx, ly, thickness, nx, ny):
    """blockMeshDict of one hex block [0, lx] x [0, ly] x [0, thickness], nx x ny x 1 cells; patches
    walls (left, right, bottom), atmosphere (top), frontAndBack (empty). Cells are numbered x first."""
    return f"""scale 1;
vertices ( (0 0 0) ({lx!r} 0 0) ({lx!r} {ly!r} 0) (0 {ly!r} 0)
           (0 0 {thickness!r}) ({lx!r} 0 {thickness!r}) ({lx!r} {ly!r} {thickness!r}) (0 {ly!r} {thickness!r}) );
blocks ( hex (0 1 2 3 4 5 6 7) ({nx} {ny} 1) simpleGrading (1 1 1) );
edges ();
boundary
(
    walls {{ type wall; faces ( (0 4 7 3) (1 2 6 5) (0 1 5 4) ); }}
    atmosphere {{ type patch; faces ( (3 7 6 2) ); }}
    frontAndBack {{ type empty; faces ( (0 3 2 1) (4 5 6 7) ); }}
);
mergePatchPairs ();
"""


def field(dimensions, internal, walls, atmosphere, cls="volScalarField"):
    return (f"dimensions {dimensions};\ninternalField {internal};\nboundaryField\n{{\n"
            f"    walls {{ {walls} }}\n    atmosphere {{ {atmosphere} }}\n    frontAndBack {{ type empty; }}\n}}\n")


def control_dict(end_time, max_co, max_dt, sample_every, probe_points):
    points = "\n".join(f"            ({x!r} {y!r} {z!r})" for x, y, z in probe_points)
    return f"""application interFoam;
startFrom startTime; startTime 0; stopAt endTime; endTime {end_time!r};
deltaT {min(max_dt, 1e-3)!r};
writeControl runTime; writeInterval {end_time!r};
purgeWrite 0; writeFormat ascii; writePrecision 8; writeCompression off;
timeFormat general; timePrecision 8; runTimeModifiable no;
adjustTimeStep yes; maxCo {max_co!r}; maxAlphaCo {max_co!r}; maxDeltaT {max_dt!r};
functions
{{
    surface
    {{
        type probes;
        libs (sampling);
        writeControl adjustableRunTime;
        writeInterval {sample_every!r};
        fields (alpha.water);
        probeLocations
        (
{points}
        );
    }}
}}
"""


FV_SCHEMES = """ddtSchemes { default Euler; }
gradSchemes { default Gauss linear; }
divSchemes
{
    div(rhoPhi,U) Gauss linearUpwind grad(U);
    div(phi,alpha) Gauss vanLeer;
    div(phirb,alpha) Gauss linear;
    div(((rho*nuEff)*dev2(T(grad(U))))) Gauss linear;
}
laplacianSchemes { default Gauss linear corrected; }
interpolationSchemes { default linear; }
snGradSchemes { default corrected; }
"""

FV_SOLUTION = """solvers
{
    "alpha.water.*"
    {
        nAlphaCorr 2; nAlphaSubCycles 1; cAlpha 1; MULESCorr yes; nLimiterIter 5;
        solver smoothSolver; smoother symGaussSeidel; tolerance 1e-8; relTol 0;
    }
    "pcorr.*" { solver PCG; preconditioner DIC; tolerance 1e-5; relTol 0; }
    p_rgh { solver PCG; preconditioner DIC; tolerance 1e-7; relTol 0.05; }
    p_rghFinal { $p_rgh; relTol 0; }
    U { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-6; relTol 0; }
}
PIMPLE { momentumPredictor no; nOuterCorrectors 1; nCorrectors 3; nNonOrthogonalCorrectors 0; }
relaxationFactors { equations { ".*" 1; } }
"""


def transport(nu_water, nu_air, sigma):
    return (f"phases (water air);\nwater {{ transportModel Newtonian; nu {nu_water!r}; rho 1000; }}\n"
            f"air {{ transportModel Newtonian; nu {nu_air!r}; rho 1; }}\nsigma {sigma!r};\n")


def write_common(case, lx, ly, nx, ny, wall_u, transport_text, control_text):
    dx = lx / nx
    foam_file(os.path.join(case, "system", "blockMeshDict"), "dictionary", "blockMeshDict",
              block_mesh(lx, ly, dx, nx, ny))
    foam_file(os.path.join(case, "system", "controlDict"), "dictionary", "controlDict", control_text)
    foam_file(os.path.join(case, "system", "fvSchemes"), "dictionary", "fvSchemes", FV_SCHEMES)
    foam_file(os.path.join(case, "system", "fvSolution"), "dictionary", "fvSolution", FV_SOLUTION)
    foam_file(os.path.join(case, "constant", "transportProperties"), "dictionary", "transportProperties",
              transport_text)
    foam_file(os.path.join(case, "constant", "g"), "uniformDimensionedVectorField", "g",
              "dimensions [0 1 -2 0 0 0 0];\nvalue (0 -9.81 0);\n")
    foam_file(os.path.join(case, "constant", "turbulenceProperties"), "dictionary", "turbulenceProperties",
              "simulationType laminar;\n")
    foam_file(os.path.join(case, "0", "U"), "volVectorField", "U",
              field("[0 1 -1 0 0 0 0]", "uniform (0 0 0)", wall_u,
                    "type pressureInletOutletVelocity; value uniform (0 0 0);"))
    foam_file(os.path.join(case, "0", "p_rgh"), "volScalarField", "p_rgh",
              field("[1 -1 -2 0 0 0 0]", "uniform 0", "type fixedFluxPressure; value uniform 0;",
                    "type totalPressure; p0 uniform 0;"))
    return dx


ALPHA_BC = ("type zeroGradient;", "type inletOutlet; inletValue uniform 0; value uniform 0;")


def cosine_fill(x0, x1, y0, y1, depth, amplitude, length, samples=16):
    """Liquid fraction of the cell [x0, x1] x [y0, y1] under y = depth + amplitude cos(pi x / L)
    (midpoint rule across the cell, exact in y)."""
    total = 0.0
    for s in range(samples):
        x = x0 + (s + 0.5) * (x1 - x0) / samples
        eta = depth + amplitude * math.cos(math.pi * x / length)
        total += min(max((eta - y0) / (y1 - y0), 0.0), 1.0)
    return total / samples


def sloshing_case(case, nx):
    """Writes the sloshing case with nx cells along the tank; returns what read_sloshing needs."""
    p = SLOSH
    dx = p["length"] / nx
    ny = round(p["height"] / dx)
    ly = ny * dx
    period = 1 / lm.sloshing_frequency(p["length"], p["depth"])
    # Probes: the cell centres of the rows within 4 cells or 2 cm of the still surface (the surface
    # stays within 5 mm of it); the rows below are full, those above empty.
    band = max(4 * dx, 0.02)
    rows = [j for j in range(ny) if abs((j + 0.5) * dx - p["depth"]) <= band]
    points = [((i + 0.5) * dx, (j + 0.5) * dx, 0.5 * dx) for j in rows for i in range(nx)]
    write_common(case, p["length"], ly, nx, ny, "type slip;", transport(1e-9, 1e-9, 0.0),
                 control_dict(p["end_time"], 0.5, period / 100, period / 50, points))
    alpha = [cosine_fill(i * dx, (i + 1) * dx, j * dx, (j + 1) * dx, p["depth"], p["amplitude"], p["length"])
             for j in range(ny) for i in range(nx)]
    foam_file(os.path.join(case, "0", "alpha.water"), "volScalarField", "alpha.water",
              field("[0 0 0 0 0 0 0]", "nonuniform List<scalar>\n" + f"{len(alpha)}\n(\n"
                    + "\n".join(f"{v:.12g}" for v in alpha) + "\n)", *ALPHA_BC))
    return {"problem": "sloshing", "cells": nx * ny, "nx": nx, "ny": ny, "dx": dx, "rows": rows,
            "end_time": p["end_time"]}


def dam_break_case(case, n):
    """Writes the dam-break case with n cells along the column's side a."""
    p = DAM
    a = p["a"]
    dx = a / n
    nx, ny = round(p["length"] * n), round(p["height"] * n)
    end = p["end_tau"] / math.sqrt(lm.G / a)
    # Probes: the floor row (front) and the column at the back wall (height).
    points = [((i + 0.5) * dx, 0.5 * dx, 0.5 * dx) for i in range(nx)]
    points += [(0.5 * dx, (j + 0.5) * dx, 0.5 * dx) for j in range(ny)]
    write_common(case, nx * dx, ny * dx, nx, ny, "type noSlip;", transport(1e-6, 1.48e-5, 0.07),
                 control_dict(end, 0.5, 1.0, end / 200, points))
    foam_file(os.path.join(case, "0", "alpha.water"), "volScalarField", "alpha.water",
              field("[0 0 0 0 0 0 0]", "uniform 0", *ALPHA_BC))
    half = 0.5 * dx
    foam_file(os.path.join(case, "system", "setFieldsDict"), "dictionary", "setFieldsDict",
              "defaultFieldValues ( volScalarFieldValue alpha.water 0 );\n"
              f"regions ( boxToCell {{ box (-1 -1 -1) ({a - half / 2!r} {a - half / 2!r} 1); "
              "fieldValues ( volScalarFieldValue alpha.water 1 ); } );\n")
    return {"problem": "dam_break", "cells": nx * ny, "nx": nx, "ny": ny, "dx": dx, "a": a, "end_time": end}


def read_probes(case):
    """(times, rows of values) of the probes function object's alpha.water file."""
    base = os.path.join(case, "postProcessing", "surface")
    times, rows = [], []
    for start in sorted(os.listdir(base), key=float):
        with open(os.path.join(base, start, "alpha.water")) as f:
            for line in f:
                if line.startswith("#") or not line.strip():
                    continue
                words = line.split()
                times.append(float(words[0]))
                rows.append([float(w) for w in words[1:]])
    return times, rows


def read_sloshing(case, info):
    p, dx, nx = SLOSH, info["dx"], info["nx"]
    base = info["rows"][0] * dx  # bottom of the lowest probed row; the rows below are full
    times, rows = read_probes(case)
    xs = [(i + 0.5) * dx for i in range(nx)]
    amp = []
    for values in rows:
        eta = [base + dx * sum(values[r * nx + i] for r in range(len(info["rows"]))) - p["depth"] for i in range(nx)]
        amp.append(lm.mode_amplitude(xs, eta, [1.0] * nx, p["length"]))
    f, change, extrema = lm.sloshing_frequency_and_decay([0.0] + times, [p["amplitude"]] + amp)
    exact = lm.sloshing_frequency(p["length"], p["depth"])
    return {"frequency": f, "frequency_error": f / exact - 1, "change_per_period": change,
            "detail": f"f = {f:.5f} Hz (linear theory {exact:.5f}), amplitude {100 * change:+.2f}% per period "
                      f"({extrema} extrema)"}


def crossing(positions, alpha):
    """The farthest position along a line of cell centres at which alpha falls through 0.5."""
    for i in range(len(alpha) - 1, -1, -1):
        if alpha[i] >= 0.5:
            if i + 1 == len(alpha):
                return positions[i]
            return positions[i] + (positions[i + 1] - positions[i]) * (alpha[i] - 0.5) / (alpha[i] - alpha[i + 1])
    return 0.0


def read_dam_break(case, info):
    dx, nx, ny, a = info["dx"], info["nx"], info["ny"], info["a"]
    times, rows = read_probes(case)
    xs = [(i + 0.5) * dx for i in range(nx)]
    ys = [(j + 0.5) * dx for j in range(ny)]
    front = [crossing(xs, r[:nx]) for r in rows]
    height = [crossing(ys, r[nx:]) for r in rows]
    front_rms, front_max = lm.martin_moyce_rms(times, front, a, "front")
    height_rms, height_max = lm.martin_moyce_rms(times, height, a, "height")
    return {"front_rms": front_rms, "height_rms": height_rms,
            "detail": f"rms Z - Z_MM {front_rms:.3f} (largest {front_max:.3f}) over {len(lm.MM_FRONT_T)} points; "
                      f"rms H - H_MM {height_rms:.3f} (largest {height_max:.3f}) over {len(lm.MM_HEIGHT_TAU)} points",
            "series": {"t": times, "front": front, "height": height}}


def run_tool(case, tool, log):
    """Runs one OpenFOAM tool in the case; returns (wall [s], cpu [s], peak resident memory [MB])."""
    start = time.monotonic()
    with open(os.path.join(case, f"log.{tool}"), "w") as out:
        p = subprocess.Popen([tool, "-case", case], stdout=out, stderr=subprocess.STDOUT, env=environment())
        _, status, usage = os.wait4(p.pid, 0)
    wall = time.monotonic() - start
    code = os.waitstatus_to_exitcode(status)
    if code != 0:
        tail = open(os.path.join(case, f"log.{tool}")).read()[-1500:]
        raise RuntimeError(f"{tool} failed (exit {code}) in {case}:\n{tail}")
    log.append(tool)
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024.0


def run(problem, n, work):
    """Writes, runs and reads one case; returns a dict: cells, errors, detail, wall, cpu, peak_mb."""
    case = os.path.join(work, f"openfoam_{problem}_{n}")
    shutil.rmtree(case, ignore_errors=True)
    info = sloshing_case(case, n) if problem == "sloshing" else dam_break_case(case, n)
    tools = ["blockMesh"] + (["setFields"] if problem == "dam_break" else []) + ["interFoam"]
    wall = cpu = peak = 0.0
    done = []
    for tool in tools:
        w, c, m = run_tool(case, tool, done)
        wall, cpu, peak = wall + w, cpu + c, max(peak, m)
    result = read_sloshing(case, info) if problem == "sloshing" else read_dam_break(case, info)
    steps = sum(1 for line in open(os.path.join(case, "log.interFoam")) if line.startswith("Time = "))
    result.update(cells=info["cells"], simulated=info["end_time"], grid=f"{info['nx']} x {info['ny']}", wall=wall,
                  cpu=cpu, peak_mb=peak,
                  steps=steps, case=case, command=" ".join(tools))
    return result


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("problem", choices=["sloshing", "dam_break"])
    ap.add_argument("--cells", type=int, required=True,
                    help="cells along the tank's length (sloshing) or the column's side a (dam break)")
    ap.add_argument("--work", default="out/openfoam_peer", help="folder for the case")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args()
    if not available():
        sys.exit("openfoam_peer.py: OpenFOAM not found (blockMesh, setFields, interFoam on the PATH; "
                 "Debian: apt-get install openfoam)")
    os.makedirs(args.work, exist_ok=True)
    r = run(args.problem, args.cells, args.work)
    if args.json:
        print(json.dumps({k: v for k, v in r.items() if k != "series"}))
    else:
        print(f"{args.problem}, {r['grid']} = {r['cells']} cells, {r['steps']} steps: {r['detail']}; "
              f"wall {r['wall']:.2f} s, cpu {r['cpu']:.2f} s, peak {r['peak_mb']:.0f} MB")
    return 0


if __name__ == "__main__":
    sys.exit(main())
