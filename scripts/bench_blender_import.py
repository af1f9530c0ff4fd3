#!/usr/bin/python3
"""Benchmark of scripts/blender_import.py: a scene through `tetfsi run`, the import with
`blender -b`, a check of what the .blend holds and one Cycles frame with motion blur.

    scripts/bench_blender_import.py --tetfsi build/apps/tetfsi [--scene data/scenes/smoke_sheets_ci.json]
                                    [--out DIR] [--samples 16] [--pixels 320] [--volumes]

Prints the seconds of each stage, the objects and frames, the largest difference between the
`velocity` attribute of every frame mesh and the vx vy vz of its PLY (turned to Z-up when the run
was Y-up; 0 means the attribute holds the file's float32 values), and writes DIR/render.png:
the middle frame seen along +y (Z-up) by an orthographic camera framing every frame's surfaces.
With --volumes the scene runs with export.volumes "vdb" (a copy of it in DIR): the fluid volume
sequence is imported too, and the check reports, at every Blender frame, whether the volume
object loaded that frame's volumes/fluid_NNNNN.vdb with its grids (density, temperature,
velocity); the render then shows the smoke.
Needs `blender` (Debian 12: apt-get install blender, Blender 3.4) and numpy in Blender's Python.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))

# Runs inside Blender on the imported .blend: compares every frame mesh with its PLY (read by the
# import script's own reader, which the ctest checks against an independent reader), then renders.
CHECK_AND_RENDER = r"""
import bpy, json, os, sys, time, numpy as np
sys.path.insert(0, %(here)r)
import blender_import as bi
outdir, pixels, samples = %(outdir)r, %(pixels)d, %(samples)d
z_up = bi.run_files_are_z_up(outdir)
worst, verts, objects = 0.0, 0, {}
lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
for name, frames in bi.surface_frames(outdir).items():
    objects[name] = len(frames)
    for k, path in frames.items():
        p, v, t = bi.read_ply(path)
        if v is None:
            continue
        if not z_up:
            p, v = bi.y_up_to_z_up(p), bi.y_up_to_z_up(v)
        m = bpy.data.objects["%%s_%%05d" %% (name, k)].data
        got = np.zeros(3 * len(m.vertices), dtype=np.float32)
        m.attributes["velocity"].data.foreach_get("vector", got)
        worst = max(worst, float(np.abs(got.reshape(-1, 3) - v).max()) if len(v) else 0.0)
        verts += len(p)
        if len(p):
            lo, hi = np.minimum(lo, p.min(axis=0)), np.maximum(hi, p.max(axis=0))
sc = bpy.context.scene
volumes, volume_files = {}, bi.volume_frames(outdir)
for name, files in volume_files.items():
    obj = bpy.data.objects[name + "_volume"]
    numbers = sorted(files)
    ok = 0
    for i, k in enumerate(numbers):
        sc.frame_set(i + 1)
        g = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.grids
        g.load()
        names = {x.name for x in g}
        ok += os.path.basename(g.frame_filepath) == os.path.basename(files[k]) and {"density", "temperature", "velocity"} <= names
    volumes[name] = {"files": len(numbers), "frames_loaded_with_grids": ok, "grids": sorted(names)}
print("BENCH " + json.dumps({"objects": objects, "volumes": volumes, "vertices": verts, "fps": sc.render.fps / sc.render.fps_base,
      "velocity_vs_ply": worst, "max_speed": max(float(np.abs(np.array(
          [d.vector[:] for d in o.data.attributes["velocity"].data] or [[0, 0, 0]])).max()) for o in sc.objects if o.type == "MESH" and "velocity" in o.data.attributes)}))
sc.frame_set((sc.frame_start + sc.frame_end) // 2)
cam = bpy.data.objects.new("bench_camera", bpy.data.cameras.new("bench_camera"))
cam.data.type = "ORTHO"
cam.data.ortho_scale = 1.1 * max(hi[0] - lo[0], hi[2] - lo[2])
cam.location = ((lo[0] + hi[0]) / 2, lo[1] - 1.0 - (hi[1] - lo[1]), (lo[2] + hi[2]) / 2)
cam.rotation_euler = (np.pi / 2, 0, 0)  # looking along +y, z up
cam.data.clip_end = 10 * (hi[1] - lo[1]) + 10
sc.collection.objects.link(cam); sc.camera = cam
sun = bpy.data.objects.new("bench_sun", bpy.data.lights.new("bench_sun", "SUN"))
sun.rotation_euler = (0.8, 0.2, 0.3); sc.collection.objects.link(sun)
sc.render.resolution_x = sc.render.resolution_y = pixels
sc.render.resolution_percentage = 100
sc.cycles.samples = samples; sc.cycles.use_denoising = False; sc.cycles.device = "CPU"
sc.render.filepath = os.path.join(%(work)r, "render.png")
start = time.monotonic()
bpy.ops.render.render(write_still=True)
print("RENDER %%.2f" %% (time.monotonic() - start))
"""


def run(cmd):
    start = time.monotonic()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if p.returncode != 0:
        sys.exit(f"FAILED ({p.returncode}): {' '.join(cmd)}\n{p.stdout}")
    return p.stdout, time.monotonic() - start


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tetfsi", required=True)
    ap.add_argument("--scene", default=os.path.join(HERE, "..", "data", "scenes", "smoke_sheets_ci.json"))
    ap.add_argument("--out", default="bench_blender_import")
    ap.add_argument("--samples", type=int, default=16)
    ap.add_argument("--pixels", type=int, default=320)
    ap.add_argument("--volumes", action="store_true", help='run with export.volumes "vdb" and import the volumes')
    args = ap.parse_args()
    blender = shutil.which("blender")
    if not blender:
        sys.exit("blender not on PATH (Debian: apt-get install blender)")
    version = subprocess.run([blender, "--version"], stdout=subprocess.PIPE, text=True).stdout.split("\n")[0]
    work = os.path.abspath(args.out)
    outdir, blend = os.path.join(work, "run"), os.path.join(work, "run.blend")
    os.makedirs(work, exist_ok=True)
    scene = args.scene
    if args.volumes:
        with open(args.scene) as f:
            js = json.load(f)
        js.setdefault("export", {})["volumes"] = "vdb"
        scene = os.path.join(work, "scene_vdb.json")
        with open(scene, "w") as f:
            json.dump(js, f, indent=2)
    _, t_run = run([args.tetfsi, "run", scene, "--out", outdir, "--quiet"])
    _, t_import = run([blender, "-b", "--factory-startup", "--python-exit-code", "1",
                       "--python", os.path.join(HERE, "blender_import.py"), "--", outdir, blend])
    expr = CHECK_AND_RENDER % {"here": HERE, "outdir": outdir, "pixels": args.pixels,
                               "samples": args.samples, "work": work}
    log, t_check = run([blender, "-b", "--factory-startup", blend, "--python-exit-code", "1", "--python-expr", expr])
    bench = json.loads(next(l[6:] for l in log.splitlines() if l.startswith("BENCH ")))
    t_render = float(next(l.split()[1] for l in log.splitlines() if l.startswith("RENDER ")))
    print(f"{version}; scene {os.path.basename(args.scene)}")
    print(f"tetfsi run {t_run:.2f} s; import {t_import:.2f} s (.blend {os.path.getsize(blend) / 1e6:.1f} MB); "
          f"check + render {t_check:.2f} s, of which Cycles {t_render:.2f} s "
          f"({args.pixels}x{args.pixels}, {args.samples} samples, motion blur)")
    print(f"objects (frames): {bench['objects']}; {bench['vertices']} vertices in all frames; {bench['fps']:g} fps")
    print(f"velocity attribute vs PLY vx vy vz: max |difference| {bench['velocity_vs_ply']:.3g} m/s; "
          f"largest component {bench['max_speed']:.3g} m/s")
    for name, v in bench["volumes"].items():
        print(f"volumes {name}: {v['files']} .vdb files, {v['frames_loaded_with_grids']} Blender frames loaded their "
              f"own file with density, temperature and velocity; grids {v['grids']}")
    print(f"render: {os.path.join(work, 'render.png')}")
    volumes_ok = all(v["files"] == v["frames_loaded_with_grids"] for v in bench["volumes"].values())
    return 0 if bench["velocity_vs_ply"] == 0.0 and volumes_ok and (bench["volumes"] or not args.volumes) else 1


if __name__ == "__main__":
    sys.exit(main())
