"""The error measures of scripts/report.py, one function per `metric` of data/report/cases.json.

Each takes a `Run` (the scene as run, its output folder, the process's stdout, the case's
`params`) and returns a `Result`: the signed error against the case's reference, a short text with
the measured and reference values, the number of unknowns, the steps taken and the simulated time
(None for static and one-shot cases). The unknowns are those of the solve the case times: fluid
pressure unknowns (fluid runner), pressure unknowns + solid dofs (coupled runner, the largest
step), 3 x nodes (solid and hex8 static runners), particles (mpm runner), fluid nodes
(bench_fluid's potential flow) and the tank's mesh nodes (bench_fluid's standing wave; about 2/3
of them liquid).
"""

import csv
import math
import os
import re
import subprocess
import sys
from dataclasses import dataclass, field

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_coaxial_rod  # noqa: E402  (reference and zero-crossing frequency of the coaxial rod)
import liquid_measures as lm  # noqa: E402  (sloshing and dam-break measures, shared with openfoam_peer.py)

G = 9.81


@dataclass
class Run:
    scene: dict          # the scene file as run (None for a bench case)
    out: str             # tetfsi's output folder (scene cases)
    stdout: str          # what the process printed
    params: dict = field(default_factory=dict)


@dataclass
class Result:
    error: float
    detail: str
    unknowns: int
    steps: int
    simulated: float = None  # simulated time [s]; None: static or a single solve
    cells: int = None        # cells of the mesh (tets), where the case states them
    also: dict = field(default_factory=dict)  # further errors of the same run: name -> (error, detail)


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def last_probe(run, name):
    return float(read_csv(os.path.join(run.out, "probes.csv"))[-1][name])


def steps_and_time(run):
    """Steps taken and simulated time from stats.csv (mpm rows each cover `substeps` steps)."""
    rows = [r for r in read_csv(os.path.join(run.out, "stats.csv")) if float(r["step"]) > 0]
    if rows and "substeps" in rows[0] and "particles" in rows[0]:
        return int(sum(float(r["substeps"]) for r in rows)), float(rows[-1]["time"])
    return len(rows), float(rows[-1]["time"]) if rows else 0.0


def unknowns(run, kind):
    """The unknowns of the case's solve (module docstring)."""
    if kind in ("fluid", "coupled", "mpm"):
        rows = read_csv(os.path.join(run.out, "stats.csv"))
        if kind == "fluid":
            return int(max(float(r["unknowns"]) for r in rows))
        if kind == "coupled":
            return int(max(float(r["pressure_unknowns"]) + float(r["solid_dofs"]) for r in rows))
        return int(max(float(r["particles"]) for r in rows))
    log = open(os.path.join(run.out, "run.log")).read()
    pattern = r"mesh: solid '[^']*': (\d+) vertices" if kind == "solid_log" else r"hex solid '[^']*': .*?(\d+) nodes"
    return 3 * sum(int(n) for n in re.findall(pattern, log))


def pipe_axis(run):
    u = last_probe(run, "u_axis")
    half = last_probe(run, "u_half_radius")
    steps, t = steps_and_time(run)
    return Result(u - 1.0, f"u(0) = {u:.4f} m/s (exact 1), u(R/2) = {half:.4f} m/s (exact 0.75)",
                  unknowns(run, "fluid"), steps, t)


def tet_cantilever_tip(run):
    p = run.params
    side = p["side"]
    exact = p["traction"] * side * side * p["length"] ** 3 / (3 * p["youngs_modulus"] * side ** 4 / 12)
    tip = -last_probe(run, "tip_y")
    rows = read_csv(os.path.join(run.out, "stats.csv"))
    return Result(tip / exact - 1, f"tip {1e3 * tip:.4f} mm (Euler-Bernoulli {1e3 * exact:.4f} mm)",
                  unknowns(run, "solid_log"), int(float(rows[-1]["load_steps"])))


def ring_castigliano(run):
    p = run.params
    inertia = p["width"] * p["thickness"] ** 3 / 12
    exact = math.pi * p["force"] * p["radius"] ** 3 / (4 * p["youngs_modulus"] * inertia)
    tip = last_probe(run, "tip_y")
    rows = read_csv(os.path.join(run.out, "stats.csv"))
    return Result(tip / exact - 1, f"tip_y {1e3 * tip:.5f} mm (Castigliano {1e3 * exact:.5f} mm)",
                  unknowns(run, "hex_log"), int(float(rows[-1]["load_steps"])))


def ball_rise(run):
    fluid = run.scene["fluid"]["density"]
    solid = run.scene["solids"][0]["material"]["density"]
    exact = G * (fluid - solid) / (solid + fluid / 2)
    rows = read_csv(os.path.join(run.out, "probes.csv"))
    t, y = float(rows[-1]["time"]), float(rows[-1]["centre_y"])
    a = 2 * y / (t * t)
    steps, sim = steps_and_time(run)
    return Result(a / exact - 1, f"a = {a:.4f} m/s^2 (exact {exact:.4f})", unknowns(run, "coupled"), steps, sim)


def floor_force(run):
    """Wall force of a heavy ball at rest on a tank's floor against Archimedes, (rho_s - rho_f) V g with
    the ball's meshed volume V at the end (contact_force and solid_volume probes)."""
    fluid = run.scene["fluid"]["density"]
    solid = run.scene["solids"][0]["material"]["density"]
    rows = read_csv(os.path.join(run.out, "probes.csv"))
    volume, force = float(rows[-1]["ball_volume"]), float(rows[-1]["floor_force_y"])
    exact = (solid - fluid) * volume * G
    volume_change = max(abs(float(r["ball_volume"]) / float(rows[0]["ball_volume"]) - 1) for r in rows)
    steps, sim = steps_and_time(run)
    return Result(force / exact - 1, f"F = {force:.4f} N (Archimedes {exact:.4f} N), ball volume within "
                  f"{volume_change:.1e}", unknowns(run, "coupled"), steps, sim)


def rod_frequency(run):
    exact, _, ratio = bench_coaxial_rod.reference(run.scene)
    f = bench_coaxial_rod.crossing_frequency(os.path.join(run.out, "probes.csv"))
    steps, sim = steps_and_time(run)
    return Result(f / exact - 1, f"f = {f:.4f} Hz (exact {exact:.4f} Hz, m_a/m = {ratio:.3f})",
                  unknowns(run, "coupled"), steps, sim)


def gas_radius(run):
    """The settled membrane against the circle of its own perimeter: a closed membrane of perimeter
    6 (the 1 x 2 rectangle) that keeps its length settles to r = 3 / pi = 0.9549 (its elastic
    stretch under the gas left, about 5e-5, is far below); Lian et al. 2014 draw 0.96. The error is
    the larger of r_0deg and r_90deg off 3 / pi; the energy lost, 1 - E(end) / E(0), is set beside
    the paper's 5%."""
    rows = read_csv(os.path.join(run.out, "probes.csv"))
    r0, r90 = float(rows[-1]["r_0deg"]), float(rows[-1]["r_90deg"])
    circle = 3 / math.pi
    e0, e90 = r0 / circle - 1, r90 / circle - 1
    lost = 1 - float(rows[-1]["energy"]) / float(rows[0]["energy"])
    steps, sim = steps_and_time(run)
    return Result(e0 if abs(e0) >= abs(e90) else e90,
                  f"r_0deg {r0:.4f}, r_90deg {r90:.4f} at t = {sim:g} (3/pi = {circle:.4f}; paper 0.96); "
                  f"energy lost {100 * lost:.2f}% (paper about 5%)",
                  unknowns(run, "mpm"), steps, sim)


def floating_draft(run):
    """Mean of the midpoints of consecutive heave extrema against the Archimedes floating position
    (tests/apps/test_liquid_run.cpp, FloatingBlockHeavesAboutTheArchimedesDraft)."""
    p = run.params
    rows = read_csv(os.path.join(run.out, "probes.csv"))
    y = [float(r["centre_y"]) for r in rows]
    ext = [y[i] for i in range(1, len(y) - 1) if (y[i] - y[i - 1]) * (y[i + 1] - y[i]) < 0]
    if len(ext) < 2:
        raise ValueError(f"{len(ext)} heave extrema: fewer than 2")
    mean = sum(0.5 * (a + b) for a, b in zip(ext, ext[1:])) / (len(ext) - 1)
    ratio = run.scene["solids"][0]["material"]["density"] / run.scene["fluid"]["density"]
    draft = ratio * p["height"]
    level = (float(rows[0]["liquid_volume"]) + p["block_area"] * draft) / p["tank_area"]
    floating = level - draft + 0.5 * p["height"] - p["release_y"]
    steps, sim = steps_and_time(run)
    return Result((mean - floating) / draft, f"heave about {1e3 * mean:.2f} mm (Archimedes {1e3 * floating:.2f} mm), "
                  f"{len(ext)} extrema", unknowns(run, "coupled"), steps, sim)


def tets(run):
    """Largest tet count of the run (stats.csv column `tets` of the fluid runner)."""
    return int(max(float(r["tets"]) for r in read_csv(os.path.join(run.out, "stats.csv"))))


def liquid_result(run, error, detail, also):
    """The Result of a fluid-runner liquid case: its steps, simulated time and tets from stats.csv,
    the tets appended to `detail`, which the `also` error (name, value) shares."""
    steps, sim = steps_and_time(run)
    n = tets(run)
    detail = f"{detail}; {n} tets"
    return Result(error, detail, unknowns(run, "fluid"), steps, sim, n, {also[0]: (also[1], detail)})


def liquid_frames(run):
    """(frame times [s], PLY paths) of the run's liquid surfaces, frame N at t = N / frame_rate."""
    folder = os.path.join(run.out, "surfaces")
    files = sorted(f for f in os.listdir(folder) if f.startswith("liquid_") and f.endswith(".ply"))
    if not files:
        raise ValueError(f"no liquid surface in {folder} (export.surfaces must be ply)")
    rate = run.scene["simulation"]["frame_rate"]
    return [int(f[7:-4]) / rate for f in files], [os.path.join(folder, f) for f in files]


def sloshing_mode(run):
    """First sloshing mode (liquid_measures.py): frequency from the zero crossings of the mode
    amplitude of the liquid surface (its up-facing triangles, area-weighted) against linear theory;
    also the amplitude change per period (sloshing_damping; 0 for an inviscid liquid)."""
    p = run.params
    times, paths = liquid_frames(run)
    amplitude = []
    for path in paths:
        xs, etas, areas = lm.top_surface_samples(*lm.read_ply(path))
        amplitude.append(lm.mode_amplitude(xs, etas, areas, p["length"]))
    f, change, extrema = lm.sloshing_frequency_and_decay(times, amplitude)
    exact = lm.sloshing_frequency(p["length"], p["depth"])
    return liquid_result(run, f / exact - 1, f"f = {f:.5f} Hz (linear theory {exact:.5f}), amplitude "
                         f"{100 * change:+.2f}% per period ({extrema} extrema)", ("sloshing_damping", change))


def dam_break_martin_moyce(run):
    """Martin & Moyce (1952) square column (liquid_measures.py): rms of Z - Z_MM over their front
    table (the front: the liquid surface's largest x) and, as dam_break_height, of H - H_MM over
    their column-height table (the height: the liquid surface's highest point on the back wall x = 0)."""
    a = run.params["a"]
    times, paths = liquid_frames(run)
    front, height = [], []
    for path in paths:
        vertices, _ = lm.read_ply(path)
        front.append(max(v[0] for v in vertices))
        wall = [v[1] for v in vertices if v[0] <= 1e-6 * a]
        height.append(max(wall) if wall else 0.0)
    front_rms, front_max = lm.martin_moyce_rms(times, front, a, "front")
    height_rms, height_max = lm.martin_moyce_rms(times, height, a, "height")
    return liquid_result(run, front_rms, f"rms Z - Z_MM {front_rms:.3f} (largest {front_max:.3f}) over "
                         f"{len(lm.MM_FRONT_T)} points; rms H - H_MM {height_rms:.3f} (largest {height_max:.3f}) "
                         f"over {len(lm.MM_HEIGHT_TAU)} points", ("dam_break_height", height_rms))


def liquid_volume_kept(run):
    """Largest |V_n / V_0 - 1| of the liquid over the run's steps (probe liquid_volume, every step);
    also the mean |volume_drift| per step (stats.csv: what the transfer to the new mesh lost before
    the volume restoration put it back; liquid_volume_drift). The scene's first region must be a box."""
    rows = read_csv(os.path.join(run.out, "probes.csv"))
    volume = [float(r["liquid_volume"]) for r in rows]
    error = max(abs(v / volume[0] - 1) for v in volume)
    lo, hi = run.scene["domain"]["lo"], run.scene["domain"]["hi"]
    region = run.scene["fluid"]["regions"][0]  # a box: its part inside the domain is the liquid at t = 0
    exact = math.prod(max(0.0, min(hi[k], region["hi"][k]) - max(lo[k], region["lo"][k])) for k in range(3))
    stats = [r for r in read_csv(os.path.join(run.out, "stats.csv")) if float(r["step"]) > 0]
    drift = [abs(float(r["volume_drift"])) for r in stats]
    mean_drift = sum(drift) / len(drift)
    return liquid_result(run, error, f"max |V/V0 - 1| {error:.2e} over {len(volume)} probe rows ({len(drift)} "
                         f"steps); drift before the restoration {mean_drift:.2e} per step on average, "
                         f"{max(drift):.2e} at worst; V0 / region's volume - 1 = {volume[0] / exact - 1:+.2e} "
                         "(the level set sampled at the nodes)", ("liquid_volume_drift", mean_drift))


def bench_row(run, case_prefix):
    """Cells of the benchmark table row whose case starts with `case_prefix`."""
    for line in run.stdout.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("|") and cells[0].startswith(case_prefix):
            return cells
    raise ValueError(f"no row '{case_prefix}...' in the benchmark's output:\n{run.stdout}")


def number(pattern, text):
    m = re.search(pattern, text)
    if not m:
        raise ValueError(f"'{pattern}' not found in '{text}'")
    return float(m.group(1).replace(",", ""))


def potential_flow_cp(run):
    cells = bench_row(run, "potential flow past a sphere")
    rms = number(r"rms ([0-9.eE+-]+)", cells[2])
    return Result(rms, cells[2].split(";")[0], int(number(r"(\d+) nodes", cells[1])), 1)


def standing_wave_period(run):
    cells = bench_row(run, "standing wave")
    err = number(r"period ([+-]?[0-9.]+)%", cells[2]) / 100
    steps = int(number(r"(\d+) steps", cells[1]))
    # standing_wave.hpp: L = 1 m, H = 0.5 m, 2.25 periods of 2 pi / omega, omega^2 = g k tanh(k H).
    k = math.pi
    period = 2 * math.pi / math.sqrt(G * k * math.tanh(k * 0.5))
    # Unknowns: the nodes of the n x 2 x (3n/4) Kuhn box (the liquid's are about 2/3 of them).
    n = int(number(r"(\d+) cells/L", cells[1]))
    decay = -number(r"amplitude decay ([+-]?[0-9.]+)%", cells[2]) / 100
    return Result(err, cells[2].split(";")[0], (n + 1) * 3 * ((3 * n) // 4 + 1), steps, 2.25 * period,
                  int(number(r"(\d+) tets", cells[1])),
                  {"standing_wave_damping": (decay, f"amplitude change {100 * decay:+.1f}% per period")})


def cavity_ghia(run):
    """Largest abs(u - u_Ghia) / U over Ghia, Ghia & Shin's 30 interior centre-line points (bench_viscous.py)."""
    frames = sorted(f for f in os.listdir(os.path.join(run.out, "fluid")) if f.endswith(".vtu"))
    # In a child process: importing VTK here would raise this process's resident memory, which the
    # later runs' peak (ru_maxrss, kept across fork and exec) would then report as their own.
    code = ("import sys; sys.path.insert(0, sys.argv[1]); import bench_viscous; "
            "print(bench_viscous.fitted_error(sys.argv[2], float(sys.argv[3])))")
    error = float(subprocess.run([sys.executable, "-c", code, os.path.dirname(os.path.abspath(__file__)),
                                  os.path.join(run.out, "fluid", frames[-1]), str(run.scene["mesh"]["edge_length"])],
                                 check=True, capture_output=True, text=True).stdout)
    steps, sim = steps_and_time(run)
    return Result(error, f"max abs(u - u_Ghia) = {error:.4f} U over 30 points", unknowns(run, "fluid"), steps, sim)


def settling_speed(run):
    """Settling speed (the last two frames) against Stokes' with Haberman & Sayre's wall factor."""
    p = run.params
    reference = 2 / 9 * (p["solid_density"] - p["fluid_density"]) * G * p["radius"] ** 2 / p["viscosity"] / p["wall_factor"]
    rows = read_csv(os.path.join(run.out, "probes.csv"))
    v = -(float(rows[-1]["centre_z"]) - float(rows[-2]["centre_z"])) / (float(rows[-1]["time"]) - float(rows[-2]["time"]))
    steps, sim = steps_and_time(run)
    return Result(v / reference - 1, f"v = {100 * v:.3f} cm/s (Stokes / wall factor {100 * reference:.3f} cm/s)",
                  unknowns(run, "coupled"), steps, sim)


METRICS = {f.__name__: f for f in (pipe_axis, tet_cantilever_tip, ring_castigliano, ball_rise, floor_force, rod_frequency,
                                   gas_radius, floating_draft, potential_flow_cp, standing_wave_period, cavity_ghia,
                                   settling_speed, sloshing_mode, dam_break_martin_moyce, liquid_volume_kept)}
