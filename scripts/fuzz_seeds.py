#!/usr/bin/env python3
"""Writes seed corpora for the libFuzzer targets (fuzz/): generated shapes (tetrahedron, cube,
octahedron, icosphere) as PLY (ASCII, binary little/big endian), OBJ, STL (ASCII, binary), OFF,
glTF; and as .vtu grids of triangles (zlib-compressed raw appended as tetfsi writes by default,
uncompressed inline base64, ASCII); a unit cube as 5 tets and as 1 hex in Gmsh .msh 2.2 and 4.1 (with a
boundary triangle and a $PhysicalNames section); checkpoints (apps/run/checkpoint.hpp) of a driver
state with .pvd lists, probes and a runner state. Usage: fuzz_seeds.py OUT_DIR  -> OUT_DIR/ply/*,
OUT_DIR/surface/* (first byte = format), OUT_DIR/vtu/*, OUT_DIR/msh/* (first byte: tets or hexes), OUT_DIR/checkpoint/* (first
byte even: payload behind a valid header; odd: whole file)."""
import base64
import math
import os
import struct
import sys
import zlib


def shapes():
    tet = ([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)], [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)])
    cv = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    cube = (cv, [t for q in quads for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))])
    ov = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    of = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    t = (1 + math.sqrt(5)) / 2
    iv = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
          (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    ifc = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
           (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
           (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    return {"tetra": tet, "cube": cube, "octa": (ov, of), "ico": (iv, ifc)}


def ply_ascii(v, f):
    h = f"ply\nformat ascii 1.0\nelement vertex {len(v)}\nproperty float x\nproperty float y\nproperty float z\n" \
        f"element face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n"
    return (h + "".join("%g %g %g\n" % p for p in v) + "".join("3 %d %d %d\n" % t for t in f)).encode()


def ply_binary(v, f, big):
    e = ">" if big else "<"
    h = (f"ply\nformat binary_{'big' if big else 'little'}_endian 1.0\nelement vertex {len(v)}\n"
         f"property float x\nproperty float y\nproperty float z\nelement face {len(f)}\n"
         f"property list uchar int vertex_indices\nend_header\n").encode()
    return h + b"".join(struct.pack(e + "3f", *p) for p in v) + b"".join(struct.pack(e + "B3i", 3, *t) for t in f)


def normal(v, t):
    a, b, c = (v[i] for i in t)
    u = [b[k] - a[k] for k in range(3)]
    w = [c[k] - a[k] for k in range(3)]
    return (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])


def stl_ascii(v, f):
    s = "solid s\n"
    for t in f:
        s += "facet normal %g %g %g\nouter loop\n" % normal(v, t)
        s += "".join("vertex %g %g %g\n" % v[i] for i in t) + "endloop\nendfacet\n"
    return (s + "endsolid s\n").encode()


def stl_binary(v, f):
    out = b"\0" * 80 + struct.pack("<I", len(f))
    for t in f:
        out += struct.pack("<3f", *normal(v, t)) + b"".join(struct.pack("<3f", *v[i]) for i in t) + b"\0\0"
    return out


def obj(v, f):
    return ("".join("v %g %g %g\n" % p for p in v) + "".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in f)).encode()


def off(v, f):
    return (f"OFF\n{len(v)} {len(f)} 0\n" + "".join("%g %g %g\n" % p for p in v) +
            "".join("3 %d %d %d\n" % t for t in f)).encode()


def gltf(v, f):
    import base64
    import json
    data = b"".join(struct.pack("<3f", *p) for p in v) + b"".join(struct.pack("<3I", *t) for t in f)
    nv = len(v) * 12
    lo = [min(p[k] for p in v) for k in range(3)]
    hi = [max(p[k] for p in v) for k in range(3)]
    doc = {"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
           "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," +
                        base64.b64encode(data).decode()}],
           "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": nv},
                           {"buffer": 0, "byteOffset": nv, "byteLength": len(data) - nv}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(v), "type": "VEC3", "min": lo, "max": hi},
                         {"bufferView": 1, "componentType": 5125, "count": 3 * len(f), "type": "SCALAR"}]}
    return json.dumps(doc).encode()


def vtu(v, f, encoding):
    """A VTK XML UnstructuredGrid of the triangles (header_type UInt64), mesh/io/vtu_writer's layout."""
    arrays = [("Float64", "Points", 3, struct.pack(f"<{3 * len(v)}d", *[c for p in v for c in p])),
              ("Int64", "connectivity", 1, struct.pack(f"<{3 * len(f)}q", *[i for t in f for i in t])),
              ("Int64", "offsets", 1, struct.pack(f"<{len(f)}q", *[3 * (k + 1) for k in range(len(f))])),
              ("UInt8", "types", 1, bytes([5] * len(f)))]
    compressor = ' compressor="vtkZLibDataCompressor"' if encoding == "zlib" else ""
    xml, appended = [], b""
    for vtk_type, name, comps, raw in arrays:
        head = f'<DataArray type="{vtk_type}" Name="{name}" NumberOfComponents="{comps}"'
        if encoding == "zlib":
            blocks = [zlib.compress(raw[k:k + 32768], 1) for k in range(0, len(raw), 32768)]
            last = len(raw) % 32768
            header = struct.pack(f"<{3 + len(blocks)}Q", len(blocks), 32768, last, *[len(b) for b in blocks])
            xml.append(f'{head} format="appended" offset="{len(appended)}"/>')
            appended += header + b"".join(blocks)
        elif encoding == "base64":
            xml.append(f'{head} format="binary">' + base64.b64encode(struct.pack("<Q", len(raw)) + raw).decode()
                       + "</DataArray>")
        else:
            code = {"Float64": "d", "Int64": "q", "UInt8": "B"}[vtk_type]
            values = struct.unpack(f"<{len(raw) // struct.calcsize(code)}{code}", raw)
            xml.append(f'{head} format="ascii">' + " ".join(map(str, values)) + "</DataArray>")
    text = (f'<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" '
            f'header_type="UInt64"{compressor}>\n<UnstructuredGrid>\n<Piece NumberOfPoints="{len(v)}" '
            f'NumberOfCells="{len(f)}">\n<PointData>\n</PointData>\n<CellData>\n</CellData>\n<Points>\n{xml[0]}\n'
            f'</Points>\n<Cells>\n' + "\n".join(xml[1:]) + "\n</Cells>\n</Piece>\n</UnstructuredGrid>\n")
    data = text.encode()
    if encoding == "zlib":
        data += b'<AppendedData encoding="raw">\n_' + appended + b"\n</AppendedData>\n"
    return data + b"</VTKFile>\n"


CUBE = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
CUBE_TETS = [(0, 1, 3, 5), (0, 3, 2, 6), (0, 5, 6, 4), (3, 6, 5, 7), (0, 3, 6, 5)]
CUBE_HEX = [(0, 1, 3, 2, 4, 5, 7, 6)]


def msh22(cells, gmsh_type):
    """Gmsh 2.2 ASCII: nodes tagged from 1, a boundary triangle (type 2), then the 3-D cells."""
    out = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "1", '3 1 "solid"', "$EndPhysicalNames",
           "$Nodes", str(len(CUBE))] + ["%d %g %g %g" % (i + 1, *p) for i, p in enumerate(CUBE)] + ["$EndNodes"]
    out += ["$Elements", str(len(cells) + 1), "1 2 2 0 1 1 2 4"]
    out += ["%d %d 2 1 1 " % (k + 2, gmsh_type) + " ".join(str(i + 1) for i in c) for k, c in enumerate(cells)]
    return ("\n".join(out + ["$EndElements"]) + "\n").encode()


def msh41(cells, gmsh_type):
    """Gmsh 4.1 ASCII: one node block (tags, then coordinates), a triangle block, a 3-D block."""
    n = len(CUBE)
    out = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", "$Entities", "0 0 0 1", "1 0 0 0 1 1 1 0 0", "$EndEntities",
           "$Nodes", "1 %d 1 %d" % (n, n), "3 1 0 %d" % n] + [str(i + 1) for i in range(n)]
    out += ["%g %g %g" % p for p in CUBE] + ["$EndNodes"]
    m = len(cells)
    out += ["$Elements", "2 %d 1 %d" % (m + 1, m + 1), "2 1 2 1", "1 1 2 4", "3 1 %d %d" % (gmsh_type, m)]
    out += ["%d " % (k + 2) + " ".join(str(i + 1) for i in c) for k, c in enumerate(cells)]
    return ("\n".join(out + ["$EndElements"]) + "\n").encode()


def fnv1a(data):
    h = 1469598103934665603
    for b in data:
        h = ((h ^ b) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return h


def checkpoint_payload(objects, warned, runner):
    """The driver state of apps/run/checkpoint.cpp, then the runner's bytes after their length."""
    def string(t):
        return struct.pack("<Q", len(t)) + t.encode()
    out = struct.pack("<dqii", 0.25, 30, 3, 3) + struct.pack("<Q", len(objects))
    for name, entries in objects.items():
        out += string(name) + struct.pack("<Q", len(entries))
        out += b"".join(struct.pack("<d", t) + string(f) for t, f in entries)
    out += struct.pack("<QQQdddQQ", 1000, 200, 0, 0.01, 0.005, 0.02, 120, 64)
    out += struct.pack("<Q", len(warned)) + b"".join(struct.pack("<Q", w) for w in warned)
    return out + struct.pack("<Q", len(runner)) + runner


def fuzz_runner_state():
    """What fuzz/fuzz_checkpoint.cpp reads: t, vector<double>, vector<bool>, vector<Vector3d>, VectorXd,
    MatrixXd, SparseMatrix<double> (2x2 identity), string, a stored size 3."""
    out = struct.pack("<d", 0.25)
    out += struct.pack("<Q3d", 3, 1.0, 2.0, 3.0) + struct.pack("<Q3B", 3, 1, 0, 1)
    out += struct.pack("<Q6d", 2, 0, 0, 0, 1, 1, 1) + struct.pack("<Q2d", 2, 0.5, 1.5)
    out += struct.pack("<qq4d", 2, 2, 1, 0, 0, 1)
    out += struct.pack("<qqq", 2, 2, 2) + struct.pack("<3i", 0, 1, 2) + struct.pack("<2i", 0, 1) + struct.pack("<2d", 1, 1)
    return out + struct.pack("<Q", 5) + b"solid" + struct.pack("<Q", 3)


def checkpoint_version():
    """kCheckpointVersion of apps/run/checkpoint.hpp."""
    import re
    here = os.path.dirname(os.path.abspath(__file__))
    text = open(os.path.join(here, "..", "apps", "run", "checkpoint.hpp")).read()
    return int(re.search(r"kCheckpointVersion = (\d+);", text).group(1))


def checkpoints():
    objects = {"solid": [(0.0, "solid/solid_00000.vtu"), (0.1, "solid/solid_00001.vtu")], "fluid": [(0.0, "f.vtu")]}
    payloads = {"plain": checkpoint_payload({}, [], b""), "lists": checkpoint_payload(objects, [3, 7], b"\0" * 16),
                "runner": checkpoint_payload(objects, [1], fuzz_runner_state())}
    out = {}
    for name, p in payloads.items():
        out[name + "_payload"] = b"\0" + p
        header = b"TETFSICK" + struct.pack("<IQ", checkpoint_version(), 0x1234567890abcdef) + struct.pack("<Q", 4) + b"fuzz"
        out[name + "_file"] = b"\1" + header + struct.pack("<QQ", len(p), fnv1a(p)) + p
    return out


def main():
    out = sys.argv[1]
    os.makedirs(os.path.join(out, "ply"), exist_ok=True)
    os.makedirs(os.path.join(out, "surface"), exist_ok=True)
    os.makedirs(os.path.join(out, "vtu"), exist_ok=True)
    os.makedirs(os.path.join(out, "msh"), exist_ok=True)
    os.makedirs(os.path.join(out, "checkpoint"), exist_ok=True)
    # fuzz_msh: first byte even reads tets, odd hexes
    for name, cells, gmsh_type, code in (("tets", CUBE_TETS, 4, b"\0"), ("hex", CUBE_HEX, 5, b"\1")):
        open(os.path.join(out, "msh", f"cube_{name}_22.msh"), "wb").write(code + msh22(cells, gmsh_type))
        open(os.path.join(out, "msh", f"cube_{name}_41.msh"), "wb").write(code + msh41(cells, gmsh_type))
    for name, data in checkpoints().items():
        open(os.path.join(out, "checkpoint", name), "wb").write(data)
    # fuzz_surface: first byte % 6 picks .obj .stl .off .ply .gltf .fbx
    for name, (v, f) in shapes().items():
        plys = {"ascii": ply_ascii(v, f), "le": ply_binary(v, f, False), "be": ply_binary(v, f, True)}
        for kind, data in plys.items():
            open(os.path.join(out, "ply", f"{name}_{kind}.ply"), "wb").write(data)
        surfaces = [(0, "obj", obj(v, f)), (1, "stl_ascii", stl_ascii(v, f)), (1, "stl_binary", stl_binary(v, f)),
                    (2, "off", off(v, f)), (3, "ply", plys["ascii"]), (4, "gltf", gltf(v, f))]
        for code, kind, data in surfaces:
            open(os.path.join(out, "surface", f"{name}_{kind}"), "wb").write(bytes([code]) + data)
        for encoding in ("zlib", "base64", "ascii"):
            open(os.path.join(out, "vtu", f"{name}_{encoding}.vtu"), "wb").write(vtu(v, f, encoding))


if __name__ == "__main__":
    main()
