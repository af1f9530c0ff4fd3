"""Loads the surface frames and fluid volumes of a tetfsi run into Blender as an animation with
motion-blur data.

Usage (Blender 3.4 or newer, no add-on, only Blender's own Python and numpy):

    blender -b --factory-startup --python scripts/blender_import.py -- OUTDIR OUT.blend [--up auto|y|z]

OUTDIR is the output folder of `tetfsi run SCENE --out OUTDIR`. The script reads every
`OUTDIR/surfaces/<object>_NNNNN.ply` (binary little-endian PLY written by tetfsi: float x y z,
optional float vx vy vz per vertex, triangles) and the frame times of `OUTDIR/<object>.pvd`
(or, for surfaces without a .pvd of their own such as `liquid` and `membrane`, of any .pvd of
the run that lists the same frame number; without any .pvd, `export.vtu: false`, frame k is at
k / simulation.frame_rate of the resolved scene in run.log), and saves OUT.blend with:

- one collection per object (solid, liquid, membrane) holding one mesh object per frame,
  `<object>_NNNNN`; its `hide_render` / `hide_viewport` are keyframed so that exactly one frame
  object of each collection is visible at each Blender frame (this works for liquid surfaces
  whose topology changes from frame to frame, renders with Cycles and Eevee, and needs no
  script in the .blend);
- on each frame mesh, the PLY's per-vertex velocity [m/s] as a point-domain FLOAT_VECTOR
  attribute named `velocity`: the attribute Cycles reads for deformation motion blur of meshes
  (as written by the Alembic/USD importers and the fluid simulator); Cycles moves each vertex
  by velocity * shutter / fps, so the velocity stays in scene units per second;
- with `export.volumes: "vdb"`, the run's OUTDIR/volumes/<object>_NNNNN.vdb (OpenVDB, grids
  `density` (smoke), `temperature` [K], `velocity` [m/s] and for a liquid `surface`) as one
  volume object `<object>_volume` per object in a collection `<object>_volume`: a Blender
  volume sequence (`is_sequence`, frame_start 1, frame_duration = number of files,
  frame_offset so that Blender frame k + 1 reads file NNNNN = k, sequence mode CLIP) when the
  files are numbered without gaps, else one volume object per file with keyframed visibility as
  for the meshes (export.every_n_frames > 1). Velocity grid `velocity` in m/s for Cycles'
  volume motion blur, and a material whose Principled Volume reads the `density` and
  `temperature` grids. A Y-up run's volumes are turned by the object's rotation (+90 degrees
  about x), the files are never rewritten;
- the scene's frame rate from the .pvd times (Blender frame k + 1 is the k-th listed frame,
  fps / fps_base = (frames - 1) / (t_last - t_first)), frame range, Cycles as render engine
  and motion blur enabled (shutter 0.5 frame); denoising off when Cycles has no
  OpenImageDenoise (Debian's build). No camera or light is made.

Up axis: Blender is Z-up. With `--up auto` (default) the script reads the run's resolved scene
in OUTDIR/run.log: if `export.up_axis` is "z" the files are already turned and are read as
they are; if it is "y" (the default of tetfsi scenes) the script turns positions and velocities
itself, (x, y, z) -> (x, -z, y), the same turn as export.up_axis "z". `--up z` / `--up y` say
what the files are without reading run.log.
"""

import argparse
import os
import re
import sys
import xml.etree.ElementTree as ET

import numpy as np

FRAME_FILE = re.compile(r"^(?P<object>.+)_(?P<frame>\d{5})\.ply$")
VOLUME_FILE = re.compile(r"^(?P<object>.+)_(?P<frame>\d{5})\.vdb$")


def read_ply(path):
    """Returns (positions (n, 3) float32, velocities (n, 3) float32 or None, triangles (m, 3))
    of a binary little-endian PLY with float vertex properties and a uchar/int face list."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply\n") or end < 0:
        raise ValueError(f"{path}: not a PLY file")
    header = data[:end].decode("ascii").splitlines()
    if "format binary_little_endian 1.0" not in header:
        raise ValueError(f"{path}: only binary_little_endian PLY is read")
    element, props, counts = None, {"vertex": [], "face": []}, {}
    for line in header:
        words = line.split()
        if words[:1] == ["element"]:
            element = words[1]
            counts[element] = int(words[2])
        elif words[:1] == ["property"] and element == "vertex":
            if words[1] != "float":
                raise ValueError(f"{path}: vertex property {words[-1]} is not float")
            props["vertex"].append(words[-1])
        elif words[:1] == ["property"] and element == "face":
            if words[1:4] != ["list", "uchar", "int"]:
                raise ValueError(f"{path}: face list is not 'list uchar int'")
    names = props["vertex"]
    nv, nf = counts.get("vertex", 0), counts.get("face", 0)
    body = end + len(b"end_header\n")
    vertices = np.frombuffer(data, dtype="<f4", count=nv * len(names), offset=body).reshape(nv, len(names))
    faces = np.frombuffer(data, dtype=np.dtype([("n", "u1"), ("i", "<i4", 3)]), count=nf,
                          offset=body + vertices.nbytes)
    if nf and np.any(faces["n"] != 3):
        raise ValueError(f"{path}: faces that are not triangles")
    column = {name: k for k, name in enumerate(names)}
    positions = vertices[:, [column["x"], column["y"], column["z"]]]
    velocities = None
    if all(c in column for c in ("vx", "vy", "vz")):
        velocities = vertices[:, [column["vx"], column["vy"], column["vz"]]]
    triangles = faces["i"].astype(np.int32)
    if nf and (triangles.min() < 0 or triangles.max() >= nv):
        raise ValueError(f"{path}: triangle index out of range")
    return positions.astype(np.float32), velocities, triangles


def y_up_to_z_up(v):
    """(x, y, z) -> (x, -z, y): +90 degrees about x, scene +y becomes +z (export.up_axis "z")."""
    return np.stack([v[:, 0], -v[:, 2], v[:, 1]], axis=1).astype(np.float32)


def pvd_times(outdir):
    """{object: {frame number: time [s]}} from every OUTDIR/*.pvd (frame number from the file name)."""
    times = {}
    for name in sorted(os.listdir(outdir)):
        if not name.endswith(".pvd"):
            continue
        frames = {}
        for ds in ET.parse(os.path.join(outdir, name)).getroot().iter("DataSet"):
            m = re.search(r"_(\d{5})\.\w+$", ds.get("file", ""))
            if m:
                frames[int(m.group(1))] = float(ds.get("timestep"))
        times[name[:-4]] = frames
    return times


def run_files_are_z_up(outdir):
    """export.up_axis of the run, from the resolved scene in OUTDIR/run.log (True: "z")."""
    axis = resolved_value(outdir, "up_axis", '"[yz]"')
    if axis is None:
        raise SystemExit(f"blender_import: no export.up_axis in {outdir}/run.log; say it with --up y|z")
    return axis == '"z"'


def surface_frames(outdir, folder="surfaces", pattern=FRAME_FILE):
    """{object: {frame number: path}} of OUTDIR/surfaces/<object>_NNNNN.ply."""
    found = {}
    folder = os.path.join(outdir, folder)
    for name in sorted(os.listdir(folder)) if os.path.isdir(folder) else []:
        m = pattern.match(name)
        if m:
            found.setdefault(m.group("object"), {})[int(m.group("frame"))] = os.path.join(folder, name)
    return found


def volume_frames(outdir):
    """{object: {frame number: path}} of OUTDIR/volumes/<object>_NNNNN.vdb."""
    return surface_frames(outdir, "volumes", VOLUME_FILE)


def resolved_value(outdir, key, pattern):
    """Last value of "key": <pattern> in the resolved scene of OUTDIR/run.log (None if absent)."""
    path = os.path.join(outdir, "run.log")
    if not os.path.exists(path):
        return None
    with open(path, encoding="utf-8", errors="replace") as f:
        values = re.findall(r'"%s":\s*(%s)' % (key, pattern), f.read())
    return values[-1] if values else None


def frame_times(objects, times, frame_rate):
    """Time [s] of every frame number: from the object's own .pvd, else from any .pvd listing it,
    else k / frame_rate (if frame_rate is known)."""
    result = {}
    for obj, frames in objects.items():
        for k in frames:
            t = times.get(obj, {}).get(k)
            if t is None:
                t = next((fr[k] for fr in times.values() if k in fr), None)
            if t is None and frame_rate:
                t = k / frame_rate
            if t is None:
                raise SystemExit(f"blender_import: no .pvd lists frame {k} of {obj}")
            if k in result and abs(result[k] - t) > 1e-9 * max(1.0, abs(t)):
                raise SystemExit(f"blender_import: frame {k} has times {result[k]} and {t} in the .pvd files")
            result[k] = t
    return result


def make_mesh(bpy, name, positions, velocities, triangles):
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(positions))
    mesh.vertices.foreach_set("co", positions.ravel())
    mesh.loops.add(3 * len(triangles))
    mesh.loops.foreach_set("vertex_index", triangles.ravel())
    mesh.polygons.add(len(triangles))
    mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * len(triangles), 3, dtype=np.int32))
    mesh.polygons.foreach_set("loop_total", np.full(len(triangles), 3, dtype=np.int32))
    mesh.update()
    mesh.validate()
    if velocities is not None:
        attr = mesh.attributes.new("velocity", "FLOAT_VECTOR", "POINT")
        attr.data.foreach_set("vector", velocities.ravel())
    return mesh


def key_visibility(obj, frame, visible):
    obj.hide_render = obj.hide_viewport = not visible
    obj.keyframe_insert("hide_render", frame=frame)
    obj.keyframe_insert("hide_viewport", frame=frame)


def show_only_at(obj, frame, last):
    """Keys the object visible at `frame` only (of Blender frames 1..last), held constant."""
    key_visibility(obj, frame, True)
    if frame > 1:
        key_visibility(obj, frame - 1, False)
    if frame < last:
        key_visibility(obj, frame + 1, False)
    for curve in obj.animation_data.action.fcurves:
        for point in curve.keyframe_points:
            point.interpolation = "CONSTANT"


def volume_material(bpy, name):
    """A material whose Principled Volume takes its density from the `density` grid (smoke) and
    its blackbody temperature from the `temperature` grid [K]."""
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    nodes = material.node_tree.nodes
    for node in list(nodes):
        nodes.remove(node)
    shader = nodes.new("ShaderNodeVolumePrincipled")
    shader.inputs["Density Attribute"].default_value = "density"
    shader.inputs["Temperature Attribute"].default_value = "temperature"
    output = nodes.new("ShaderNodeOutputMaterial")
    material.node_tree.links.new(shader.outputs["Volume"], output.inputs["Volume"])
    return material


def import_volumes(bpy, scene, name, frames, times, blender_frame, z_up):
    """The volume files of one object as a Blender volume sequence (numbers without gaps) or as
    one volume object per file with keyframed visibility."""
    collection = bpy.data.collections.new(f"{name}_volume")
    scene.collection.children.link(collection)
    material = volume_material(bpy, f"{name}_volume")
    numbers = sorted(frames)
    sequence = numbers == list(range(numbers[0], numbers[0] + len(numbers))) and \
        [blender_frame[k] for k in numbers] == list(range(blender_frame[numbers[0]], blender_frame[numbers[0]] + len(numbers)))
    parts = [(f"{name}_volume", numbers[:1])] if sequence else [(f"{name}_volume_{k:05d}", [k]) for k in numbers]
    for label, ks in parts:
        volume = bpy.data.volumes.new(label)
        volume.filepath = os.path.abspath(frames[ks[0]])
        if sequence:
            # Blender reads file number (frame - frame_start + 1) + frame_offset at a scene frame.
            volume.is_sequence = True
            volume.frame_start = blender_frame[numbers[0]]
            volume.frame_duration = len(numbers)
            volume.frame_offset = numbers[0] - 1
            volume.sequence_mode = "CLIP"
        if not volume.grids.load():  # the grids' names are needed to name the velocity grid
            raise SystemExit(f"blender_import: {frames[ks[0]]}: {volume.grids.error_message}")
        volume.velocity_grid = "velocity"
        volume.velocity_unit = "SECOND"
        volume.materials.append(material)
        obj = bpy.data.objects.new(label, volume)
        if not z_up:
            obj.rotation_euler = (np.pi / 2, 0.0, 0.0)  # (x, y, z) -> (x, -z, y), as y_up_to_z_up
        obj["tetfsi_time"] = times[ks[0]]
        collection.objects.link(obj)
        if not sequence:
            show_only_at(obj, blender_frame[ks[0]], len(blender_frame))
    print(f"blender_import: {name}: {len(numbers)} volume frames"
          f"{' as a volume sequence' if sequence else ' as one volume object each'}")


def main(argv):
    import bpy

    parser = argparse.ArgumentParser(prog="blender -b --python blender_import.py --")
    parser.add_argument("outdir", help="output folder of tetfsi run")
    parser.add_argument("blend", help=".blend file to write")
    parser.add_argument("--up", choices=["auto", "y", "z"], default="auto",
                        help="up axis of the files (auto: export.up_axis in run.log)")
    args = parser.parse_args(argv)

    objects = surface_frames(args.outdir)
    volumes = volume_frames(args.outdir)
    if not objects and not volumes:
        raise SystemExit(f"blender_import: no surfaces/<object>_NNNNN.ply or volumes/<object>_NNNNN.vdb in {args.outdir}")
    rate = resolved_value(args.outdir, "frame_rate", r"[0-9.eE+-]+")
    listed = {name: dict(frames) for name, frames in objects.items()}
    for name, frames in volumes.items():
        listed.setdefault(name, {}).update(frames)
    times = frame_times(listed, pvd_times(args.outdir), float(rate) if rate else None)
    numbers = sorted(times)
    t = np.array([times[k] for k in numbers])
    if len(t) > 1 and np.any(np.diff(t) <= 0):
        raise SystemExit("blender_import: frame times do not increase with the frame number")
    rate = (len(t) - 1) / (t[-1] - t[0]) if len(t) > 1 else 24.0
    z_up = run_files_are_z_up(args.outdir) if args.up == "auto" else args.up == "z"

    scene = bpy.context.scene
    for obj in list(scene.collection.all_objects):  # the factory scene's cube, camera and light
        bpy.data.objects.remove(obj)
    for collection in list(bpy.data.collections):  # and its empty "Collection"
        if not collection.all_objects:
            bpy.data.collections.remove(collection)
    scene.render.fps = max(1, round(rate))
    scene.render.fps_base = scene.render.fps / rate
    scene.frame_start, scene.frame_end = 1, len(numbers)
    scene.render.engine = "CYCLES"
    scene.render.use_motion_blur = True
    scene.render.motion_blur_shutter = 0.5
    try:  # Debian's Blender is built without OpenImageDenoise: rendering would stop with an error
        import _cycles
        if not _cycles.with_openimagedenoise:
            scene.cycles.use_denoising = False
    except (ImportError, AttributeError):
        pass
    blender_frame = {k: i + 1 for i, k in enumerate(numbers)}

    for name, frames in sorted(objects.items()):
        collection = bpy.data.collections.new(name)
        scene.collection.children.link(collection)
        for k, path in sorted(frames.items()):
            positions, velocities, triangles = read_ply(path)
            if not z_up:
                positions = y_up_to_z_up(positions)
                velocities = None if velocities is None else y_up_to_z_up(velocities)
            label = f"{name}_{k:05d}"
            obj = bpy.data.objects.new(label, make_mesh(bpy, label, positions, velocities, triangles))
            obj["tetfsi_time"] = times[k]
            collection.objects.link(obj)
            show_only_at(obj, blender_frame[k], len(numbers))
        print(f"blender_import: {name}: {len(frames)} frames")
    for name, frames in sorted(volumes.items()):
        import_volumes(bpy, scene, name, frames, times, blender_frame, z_up)
    scene.frame_set(1)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.blend))
    print(f"blender_import: wrote {args.blend}: {len(numbers)} frames at {rate:g} fps, "
          f"{'Z-up files' if z_up else 'Y-up files turned to Z-up'}")


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
