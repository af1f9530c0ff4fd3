"""Renders tetfsi surface frames (PLY) to a PNG with Blender's Cycles, for pictures of the liquid
surface (data/scenes/pictures/, shown in data/scenes/README.md).

Usage (Blender 3.4 or newer, headless; Debian: apt-get install blender):

    blender -b --factory-startup --python scripts/render_surfaces.py -- \\
        --liquid OUT/surfaces/liquid_00012.ply [--solid OUT/surfaces/bowl_00012.ply ...] \\
        --box 0 0 0 0.8 0.75 0.8 --view 35 25 2.0 --size 480 360 --samples 16 --out frame.png

The PLY files are read with scripts/blender_import.py's reader (binary little-endian, tetfsi's
layout) and turned from the scenes' Y-up to Blender's Z-up, (x, y, z) -> (x, -z, y). The liquid
is a light blue glossy surface with smooth shading (what a user's import would show: the
surface's own normals, no added smoothing), solids are matte orange, the container box (--box lo
hi, scene coordinates) is drawn as a floor and thin edges. The camera looks at the box centre from
--view azimuth [deg, about the up axis, from +x scene], elevation [deg] and distance [m], with a sun
light and a grey world. Cycles on the CPU at --samples samples per pixel, no denoiser.
"""

import argparse
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_import import read_ply, y_up_to_z_up  # noqa: E402


def parse():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--liquid", action="append", default=[], help="liquid surface PLY (repeatable)")
    p.add_argument("--solid", action="append", default=[], help="solid surface PLY (repeatable)")
    p.add_argument("--box", type=float, nargs=6, metavar=("XLO", "YLO", "ZLO", "XHI", "YHI", "ZHI"),
                   help="container box in scene (Y-up) coordinates [m]")
    p.add_argument("--view", type=float, nargs=3, default=[35.0, 25.0, 2.0], metavar=("AZIMUTH", "ELEVATION", "DIST"))
    p.add_argument("--target", type=float, nargs=3, default=None, help="look-at point, scene coordinates [m]")
    p.add_argument("--size", type=int, nargs=2, default=[480, 360])
    p.add_argument("--samples", type=int, default=16)
    p.add_argument("--out", required=True)
    return p.parse_args(argv)


def material(name, color, roughness, metallic=0.0):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Metallic"].default_value = metallic
    return m


def add_mesh(name, path, mat):
    positions, _, triangles = read_ply(path)
    positions = y_up_to_z_up(positions)
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(positions.tolist(), [], triangles.tolist())
    mesh.update()
    mesh.polygons.foreach_set("use_smooth", np.ones(len(mesh.polygons), dtype=bool))
    obj = bpy.data.objects.new(name, mesh)
    obj.data.materials.append(mat)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def add_box(lo, hi, mat_floor, mat_edge):
    lo, hi = np.array(lo), np.array(hi)
    to_z = lambda p: (p[0], -p[2], p[1])  # noqa: E731
    # Floor: the box's bottom face (scene y = lo.y), slightly below so that the liquid sits on it.
    y = lo[1] - 1e-3
    corners = [to_z((lo[0], y, lo[2])), to_z((hi[0], y, lo[2])), to_z((hi[0], y, hi[2])), to_z((lo[0], y, hi[2]))]
    mesh = bpy.data.meshes.new("floor")
    mesh.from_pydata(corners, [], [(0, 1, 2, 3)])
    floor = bpy.data.objects.new("floor", mesh)
    floor.data.materials.append(mat_floor)
    bpy.context.scene.collection.objects.link(floor)
    # Edges: thin cylinders along the 12 edges.
    r = 0.004 * float(np.max(hi - lo))
    pts = [np.array([x, yy, z]) for x in (lo[0], hi[0]) for yy in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    for i in range(8):
        for j in range(i + 1, 8):
            d = pts[j] - pts[i]
            if np.count_nonzero(np.abs(d) > 1e-12) != 1:
                continue
            a, b = np.array(to_z(pts[i])), np.array(to_z(pts[j]))
            bpy.ops.mesh.primitive_cylinder_add(radius=r, depth=float(np.linalg.norm(b - a)), location=tuple((a + b) / 2))
            cyl = bpy.context.active_object
            axis = (b - a) / np.linalg.norm(b - a)
            cyl.rotation_mode = "QUATERNION"
            cyl.rotation_quaternion = axis_to_quaternion(axis)
            cyl.data.materials.append(mat_edge)


def axis_to_quaternion(axis):
    """Rotation taking +z to `axis` (unit)."""
    z = np.array([0.0, 0.0, 1.0])
    c = float(np.dot(z, axis))
    if c > 1 - 1e-9:
        return (1.0, 0.0, 0.0, 0.0)
    if c < -1 + 1e-9:
        return (0.0, 1.0, 0.0, 0.0)
    v = np.cross(z, axis)
    w = 1 + c
    q = np.array([w, *v])
    q /= np.linalg.norm(q)
    return tuple(q)


def main():
    args = parse()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = args.samples
    scene.cycles.use_denoising = False
    scene.render.resolution_x, scene.render.resolution_y = args.size
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.image_settings.compression = 100
    scene.world = bpy.data.worlds.new("world")
    scene.world.use_nodes = True
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.55, 0.58, 0.62, 1.0)
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.8

    water = material("liquid", (0.35, 0.6, 0.9), 0.15)
    solid = material("solid", (0.9, 0.45, 0.15), 0.6)
    floor = material("floor", (0.8, 0.8, 0.78), 0.9)
    edge = material("edge", (0.1, 0.1, 0.1), 0.8)
    for k, path in enumerate(args.liquid):
        add_mesh(f"liquid{k}", path, water)
    for k, path in enumerate(args.solid):
        add_mesh(f"solid{k}", path, solid)
    if args.box:
        add_box(args.box[:3], args.box[3:], floor, edge)

    if args.target is not None:
        target = np.array(args.target)
    elif args.box:
        target = 0.5 * (np.array(args.box[:3]) + np.array(args.box[3:]))
    else:
        target = np.zeros(3)
    target = np.array([target[0], -target[2], target[1]])
    az, el, dist = math.radians(args.view[0]), math.radians(args.view[1]), args.view[2]
    # Azimuth from scene +x about the up axis (Blender +z), towards scene +z (Blender -y).
    offset = dist * np.array([math.cos(el) * math.cos(az), -math.cos(el) * math.sin(az), math.sin(el)])
    cam_data = bpy.data.cameras.new("camera")
    cam_data.lens = 35
    cam = bpy.data.objects.new("camera", cam_data)
    scene.collection.objects.link(cam)
    cam.location = tuple(target + offset)
    direction = -offset / np.linalg.norm(offset)
    cam.rotation_mode = "QUATERNION"
    # Camera looks along its -z with +y up: build the rotation from the look direction.
    from mathutils import Vector
    cam.rotation_quaternion = Vector(tuple(direction)).to_track_quat("-Z", "Y")
    scene.camera = cam

    sun_data = bpy.data.lights.new("sun", type="SUN")
    sun_data.energy = 3.0
    sun = bpy.data.objects.new("sun", sun_data)
    sun.rotation_euler = (math.radians(40), math.radians(15), math.radians(30))
    scene.collection.objects.link(sun)

    scene.render.filepath = os.path.abspath(args.out)
    bpy.ops.render.render(write_still=True)
    print(f"render_surfaces: wrote {args.out}")


main()
