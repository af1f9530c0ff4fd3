#!/usr/bin/python3
"""Checks scripts/blender_import.py with Blender on the spinning sheet of test_cli_run.cpp.

The sheet turns at omega = 2 rad/s about the scene's y axis through c = (0.1, 0, 0); 5 frames at
10 frames/s. The run goes through `tetfsi run` twice, export.up_axis "y" (the script turns the
files) and "z" (files read as they are), each is imported with `blender -b`, and a second Blender
process opens the .blend and reports what it holds. Checked:

- one collection `sheet` with sheet_00000..sheet_00004, frame range 1..5, fps / fps_base = 10,
  Cycles with motion blur, exactly the frame's object visible (render and viewport) at each frame;
- frame 3: vertex positions and the `velocity` point attribute equal the PLY's x y z and vx vy vz
  (float32, bit for bit; the Y-up run's turned by (x, y, z) -> (x, -z, y)), and the velocity is
  omega x (x - c) in Z-up coordinates (omega = (0, 0, 2), |error| < 1e-5 m/s);
- Cycles reads the attribute: frame 3 is rendered from above (orthographic camera, transparent
  film: alpha = coverage) with the velocity set to 0 and to (U, 0, 0). A blur by a uniform
  translation over the shutter convolves the image with a box of width D along x, so the
  variance of the alpha-weighted x grows by D^2 / 12; D = sqrt(12 (var_U - var_0)) must be
  U * shutter / fps (U = 4 m/s, shutter 0.5 frame, 10 fps: 0.2 m = 16 pixels of 12.5 mm), to 5%.

- a liquid surface, whose topology changes from frame to frame (data/scenes/dam_break_ci.json,
  Y-up): one `liquid_NNNNN` object per PLY frame with the PLY's vertex and triangle counts, and
  the last frame's positions and velocity equal to the PLY's turned to Z-up.
- the same run's OpenVDB volumes (export.volumes "vdb"): one volume object `fluid_volume`, a
  volume sequence over Blender frames 1..N; at each Blender frame k + 1 the evaluated volume has
  loaded volumes/fluid_<k>.vdb with the grids density, temperature (FLOAT), velocity
  (VECTOR_FLOAT) and surface (the liquid's level set), voxel size the run.log's, velocity grid
  `velocity` in m/s, the object turned +90 degrees about x (Y-up run); and the script keeps one
  volume object per file, each visible at its own frame only, when the numbers have gaps
  (export.every_n_frames 2).

Exit 77 (ctest SKIP_RETURN_CODE) when `blender` is not on PATH.
Usage: blender_import_check.py --tetfsi BIN --script scripts/blender_import.py [--keep DIR]
"""

import argparse
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time

SCENE = {
    "simulation": {"end_time": 0.4, "dt": 0.02, "frame_rate": 10},
    "solids": [{"name": "sheet", "geometry": {"type": "sheet", "size": [0.6, 0.3], "thickness": 0.01},
                "material": {"density": 500, "youngs_modulus": 1e6, "poissons_ratio": 0.3},
                "motion": {"type": "rotation", "axis": [0, 2, 0], "center": [0.1, 0, 0],
                           "angular_velocity": 2}}],
}
FRAMES, FPS, U, SHUTTER = 5, 10.0, 4.0, 0.5
PIXELS, ORTHO = 128, 1.6  # 1.6 m across 128 pixels: 12.5 mm per pixel

# Runs in the second Blender process (bpy): prints one line "CHECK <json>".
REPORT = r"""
import bpy, json
sc = bpy.context.scene
out = {"fps": sc.render.fps / sc.render.fps_base, "range": [sc.frame_start, sc.frame_end],
       "engine": sc.render.engine, "motion_blur": sc.render.use_motion_blur,
       "shutter": sc.render.motion_blur_shutter,
       "collections": {c.name: sorted(o.name for o in c.objects) for c in bpy.data.collections},
       "visible": {}}
for f in range(sc.frame_start, sc.frame_end + 1):
    sc.frame_set(f)
    out["visible"][f] = sorted(o.name for o in sc.objects if not o.hide_render and not o.hide_viewport)
m = bpy.data.objects["sheet_00003"].data
out["co"] = [list(v.co) for v in m.vertices]
out["velocity"] = [list(d.vector) for d in m.attributes["velocity"].data]
out["velocity_domain"] = [m.attributes["velocity"].domain, m.attributes["velocity"].data_type]
out["triangles"] = len(m.polygons)
print("CHECK " + json.dumps(out))
"""

# Second process on the liquid run: prints "LIQUID <json>" (counts per frame, last frame's data).
LIQUID = r"""
import bpy, json
objs = sorted(bpy.data.collections["liquid"].objects, key=lambda o: o.name)
last = objs[-1].data
print("LIQUID " + json.dumps({"counts": {o.name: [len(o.data.vertices), len(o.data.polygons)] for o in objs},
      "last": objs[-1].name, "co": [list(v.co) for v in last.vertices],
      "velocity": [list(d.vector) for d in last.attributes["velocity"].data]}))
""" + r"""
sc = bpy.context.scene
vols = sorted(o.name for o in bpy.data.collections["fluid_volume"].objects)
v = bpy.data.objects[vols[0]]
out = {"objects": vols, "sequence": [v.data.is_sequence, v.data.frame_start, v.data.frame_duration, v.data.sequence_mode],
       "velocity_grid": [v.data.velocity_grid, v.data.velocity_unit], "rotation": list(v.rotation_euler),
       "range": [sc.frame_start, sc.frame_end], "frames": {}}
for f in range(sc.frame_start, sc.frame_end + 1):
    sc.frame_set(f)
    g = v.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.grids
    g.load()
    out["frames"][f] = {"file": g.frame_filepath, "loaded": g.is_loaded, "error": g.error_message,
                        "grids": sorted([x.name, x.data_type] for x in g),
                        "voxel": [x.matrix_object[0][0] for x in g if x.name == "density"]}
print("VOLUME " + json.dumps(out))
"""

# Second process on the every-second-frame volume run: visible volume objects per Blender frame.
VOLUME_GAPS = r"""
import bpy, json
sc = bpy.context.scene
vis = {}
for f in range(sc.frame_start, sc.frame_end + 1):
    sc.frame_set(f)
    vis[f] = sorted(o.name for o in bpy.data.collections["fluid_volume"].objects if not o.hide_render and not o.hide_viewport)
print("GAPS " + json.dumps({"visible": vis, "files": {o.name: o.data.filepath for o in bpy.data.collections["fluid_volume"].objects}}))
"""

# Renders Blender frame 4 from above (orthographic) with the velocity attribute set to (u, 0, 0):
# prints "XVAR <u> <variance>", the variance [pixel^2] of x weighted by alpha.
RENDER = r"""
import bpy, numpy as np
sc = bpy.context.scene
sc.frame_set(4)
cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
cam.data.type = "ORTHO"; cam.data.ortho_scale = %(ortho)r
cam.location = (0.1, 0.0, 2.0)
sc.collection.objects.link(cam); sc.camera = cam
sc.render.resolution_x = sc.render.resolution_y = %(pixels)d
sc.render.resolution_percentage = 100
sc.render.film_transparent = True
sc.cycles.samples = 64; sc.cycles.use_denoising = False; sc.cycles.device = "CPU"
attr = bpy.data.objects["sheet_00003"].data.attributes["velocity"]
for u in (0.0, %(u)r):
    attr.data.foreach_set("vector", [u, 0.0, 0.0] * len(attr.data))
    sc.render.filepath = "%(dir)s/render_%%g.png" %% u
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(sc.render.filepath)
    alpha = np.array(img.pixels[:]).reshape(%(pixels)d, %(pixels)d, 4)[..., 3]
    m = alpha.sum(axis=0); x = np.arange(len(m))
    mean = (m * x).sum() / m.sum()
    print("XVAR", u, (m * (x - mean) ** 2).sum() / m.sum())
"""


def read_ply(path):
    """Positions, velocities (lists of float32 triples) and the face count of a tetfsi PLY."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").split("\n")
    nv = int(next(l for l in header if l.startswith("element vertex")).split()[2])
    nf = int(next(l for l in header if l.startswith("element face")).split()[2])
    props = [l.split()[2] for l in header if l.startswith("property float")]
    assert props == ["x", "y", "z", "vx", "vy", "vz"], props
    rows = [struct.unpack_from("<6f", data, end + 24 * i) for i in range(nv)]
    return [list(r[:3]) for r in rows], [list(r[3:]) for r in rows], nf


def turn(v):
    return [v[0], -v[2], v[1]]


def run(cmd, **kw):
    start = time.monotonic()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, **kw)
    if p.returncode != 0:
        sys.exit(f"FAILED ({p.returncode}): {' '.join(cmd)}\n{p.stdout}")
    return p.stdout, time.monotonic() - start


def tagged(output, tag):
    return [l[len(tag) + 1:] for l in output.splitlines() if l.startswith(tag + " ")]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tetfsi", required=True)
    ap.add_argument("--script", required=True)
    ap.add_argument("--dam-break", required=True, help="data/scenes/dam_break_ci.json")
    ap.add_argument("--keep", help="work in this folder and keep it")
    args = ap.parse_args()
    blender = shutil.which("blender")
    if not blender:
        print("blender not on PATH: skipped")
        return 77
    version = subprocess.run([blender, "--version"], stdout=subprocess.PIPE, text=True).stdout.split("\n")[0]
    work = args.keep or tempfile.mkdtemp(prefix="blender_import_")
    os.makedirs(work, exist_ok=True)
    failures = []

    def expect(ok, what):
        print(("ok   " if ok else "FAIL ") + what)
        if not ok:
            failures.append(what)

    results = {}
    for axis in ("y", "z"):
        scene = dict(SCENE, export={"up_axis": axis})
        scene_file, out, blend = (os.path.join(work, n) for n in (f"spin_{axis}.json", f"out_{axis}", f"spin_{axis}.blend"))
        with open(scene_file, "w") as f:
            json.dump(scene, f)
        _, t_run = run([args.tetfsi, "run", scene_file, "--out", out, "--quiet"])
        log, t_import = run([blender, "-b", "--factory-startup", "--python-exit-code", "1",
                             "--python", args.script, "--", out, blend])
        report, t_check = run([blender, "-b", "--factory-startup", blend, "--python-exit-code", "1",
                               "--python-expr", REPORT])
        print(f"{version}, up_axis {axis}: tetfsi run {t_run:.2f} s, import {t_import:.2f} s, "
              f"check {t_check:.2f} s; " + "; ".join(tagged(log, "blender_import:")))
        results[axis] = (json.loads(tagged(report, "CHECK")[0]), read_ply(os.path.join(out, "surfaces", "sheet_00003.ply")))

    names = [f"sheet_{k:05d}" for k in range(FRAMES)]
    for axis, (got, (positions, velocities, nf)) in results.items():
        expect(got["collections"] == {"sheet": names}, f"{axis}: collection sheet holds {names}")
        expect(got["range"] == [1, FRAMES] and abs(got["fps"] - FPS) < 1e-9,
               f"{axis}: frames 1..{FRAMES} at {FPS} fps (got {got['range']} at {got['fps']})")
        expect(got["engine"] == "CYCLES" and got["motion_blur"], f"{axis}: Cycles with motion blur")
        expect(all(got["visible"][str(f)] == [names[f - 1]] for f in range(1, FRAMES + 1)),
               f"{axis}: one frame object visible per frame: {got['visible']}")
        expect(got["velocity_domain"] == ["POINT", "FLOAT_VECTOR"], f"{axis}: velocity is a POINT FLOAT_VECTOR")
        expect(got["triangles"] == nf, f"{axis}: {nf} triangles")
        fix = turn if axis == "y" else (lambda v: v)
        expect(got["co"] == [fix(p) for p in positions], f"{axis}: frame 3 positions equal the PLY's")
        expect(got["velocity"] == [fix(v) for v in velocities], f"{axis}: frame 3 velocity equals the PLY's vx vy vz")
        worst = 0.0
        for x, v in zip(got["co"], got["velocity"]):  # omega x (x - c), omega = (0, 0, 2), c = (0.1, 0, 0)
            expected = [-2 * x[1], 2 * (x[0] - 0.1), 0.0]
            worst = max(worst, math.dist(v, expected))
        expect(worst < 1e-5, f"{axis}: velocity = omega x (x - c) to {worst:.2e} m/s")
    expect(results["y"][0]["co"] == results["z"][0]["co"] and results["y"][0]["velocity"] == results["z"][0]["velocity"],
           "the Y-up run turned by the script equals the Z-up run")

    out, blend = os.path.join(work, "out_dam"), os.path.join(work, "dam.blend")
    with open(args.dam_break) as f:
        dam = json.load(f)
    dam["export"]["volumes"] = "vdb"
    dam_file = os.path.join(work, "dam_vdb.json")
    with open(dam_file, "w") as f:
        json.dump(dam, f)
    _, t_run = run([args.tetfsi, "run", dam_file, "--out", out, "--quiet"])
    _, t_import = run([blender, "-b", "--factory-startup", "--python-exit-code", "1",
                       "--python", args.script, "--", out, blend])
    report, _ = run([blender, "-b", "--factory-startup", blend, "--python-exit-code", "1", "--python-expr", LIQUID])
    got = json.loads(tagged(report, "LIQUID")[0])
    plys = sorted(n for n in os.listdir(os.path.join(out, "surfaces")) if n.startswith("liquid_"))
    counts = {}
    for n in plys:
        p, v, nf = read_ply(os.path.join(out, "surfaces", n))
        counts[n[:-4]] = [len(p), nf]
    print(f"dam_break_ci: tetfsi run {t_run:.2f} s, import {t_import:.2f} s; liquid frames {counts}")
    expect(got["counts"] == counts and len(set(c[0] for c in counts.values())) > 1,
           f"liquid: one object per PLY frame with its (changing) vertex and triangle counts: {got['counts']}")
    expect(got["last"] == plys[-1][:-4] and got["co"] == [turn(x) for x in p] and got["velocity"] == [turn(x) for x in v],
           f"liquid: {got['last']} positions and velocity equal the PLY's turned to Z-up")

    vol = json.loads(tagged(report, "VOLUME")[0])
    vdbs = sorted(n for n in os.listdir(os.path.join(out, "volumes")))
    with open(os.path.join(out, "run.log")) as f:
        voxel = float(re.search(r"voxel size of ([0-9.eE+-]+) m", f.read()).group(1))
    n = len(vdbs)
    print(f"dam_break_ci volumes: {n} files; Blender: {vol['objects']}, sequence {vol['sequence']}")
    expect(vol["objects"] == ["fluid_volume"] and vol["sequence"] == [True, 1, n, "CLIP"] and vol["range"] == [1, n],
           f"volumes: one object fluid_volume, a sequence over frames 1..{n}")
    expect(vol["velocity_grid"] == ["velocity", "SECOND"], "volumes: velocity grid `velocity` in m/s")
    expect(abs(vol["rotation"][0] - math.pi / 2) < 1e-6 and vol["rotation"][1:] == [0, 0],
           f"volumes: Y-up files turned by the object (+90 degrees about x): {vol['rotation']}")
    grids = [["density", "FLOAT"], ["surface", "FLOAT"], ["temperature", "FLOAT"], ["velocity", "VECTOR_FLOAT"]]
    for f in range(1, n + 1):
        got_f = vol["frames"][str(f)]
        expect(os.path.basename(got_f["file"]) == f"fluid_{f - 1:05d}.vdb" and got_f["loaded"] and not got_f["error"],
               f"volumes: Blender frame {f} loads {os.path.basename(got_f['file'])} {got_f['error']}")
        expect(got_f["grids"] == grids and all(abs(h - voxel) <= 1e-5 * voxel for h in got_f["voxel"]),
               f"volumes: frame {f} grids {got_f['grids']}, voxel {got_f['voxel']} (run.log: {voxel:g} m, 6 digits)")

    dam["export"]["every_n_frames"] = 2
    with open(dam_file, "w") as f:
        json.dump(dam, f)
    out2, blend2 = os.path.join(work, "out_dam2"), os.path.join(work, "dam2.blend")
    run([args.tetfsi, "run", dam_file, "--out", out2, "--quiet"])
    run([blender, "-b", "--factory-startup", "--python-exit-code", "1", "--python", args.script, "--", out2, blend2])
    gaps = json.loads(tagged(run([blender, "-b", "--factory-startup", blend2, "--python-exit-code", "1",
                                  "--python-expr", VOLUME_GAPS])[0], "GAPS")[0])
    numbers = sorted(int(n[6:11]) for n in os.listdir(os.path.join(out2, "volumes")))
    expected = {str(i + 1): [f"fluid_volume_{k:05d}"] for i, k in enumerate(numbers)}
    expect(numbers[1] - numbers[0] == 2 and gaps["visible"] == expected and
           all(os.path.basename(p) == name[-5:].join(["fluid_", ".vdb"]) for name, p in gaps["files"].items()),
           f"volumes every 2nd frame: one object per file, visible at its frame only: {gaps['visible']}")

    rendered, t_render = run([blender, "-b", os.path.join(work, "spin_z.blend"), "--python-exit-code", "1",
                              "--python-expr", RENDER % {"ortho": ORTHO, "pixels": PIXELS, "u": U, "dir": work}])
    var = {float(l.split()[0]): float(l.split()[1]) for l in tagged(rendered, "XVAR")}
    expected = U * SHUTTER / FPS
    blur = math.sqrt(max(0.0, 12 * (var.get(U, 0.0) - var.get(0.0, 0.0)))) * ORTHO / PIXELS
    expect(abs(blur - expected) <= 0.05 * expected,
           f"Cycles motion blur from the velocity attribute: x variance {var} px^2, blur {blur:.4f} m, "
           f"expected U shutter / fps = {expected:.4f} m ({t_render:.1f} s)")
    if not args.keep:
        shutil.rmtree(work)
    print("PASSED" if not failures else f"{len(failures)} FAILED")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
