#!/usr/bin/python3
"""Opens the output of the CI flagship scene (data/scenes/smoke_sheets_ci.json) with ParaView's
own Python (pvpython) and checks what a ParaView user gets (issue 20, "output that renderers read").

The scene runs through `tetfsi run` (0.4 s, 5 frames at 10 frames/s, default export settings:
zlib-compressed .vtu with Float32 fields, PLY surfaces). In pvpython, for fluid.pvd,
deflector.pvd and catcher.pvd (OpenDataFile, i.e. ParaView's PVD reader):

- the reader's TimestepValues are the `timestep` values of the .pvd, parsed here without
  ParaView, and the frame times k / frame_rate (to 1e-9 s);
- at each time ParaView loads that time's file: its point and cell counts are the counts in the
  file's <Piece> header, the sum of every field is the sum of that file's array (decoded here
  with Python's zlib from the raw appended data, summed in the same order: equal to the bit),
  and the field names are the ones tetfsi writes, the fields as 32-bit floats, the points as
  64-bit;
- the fields change with time (the sums differ between the first and the last frame; the
  sheets' largest displacement grows from 0 at t = 0), so a reader stuck on one file fails.

Exit 77 (ctest SKIP_RETURN_CODE) when `pvpython` is not on PATH (Debian: python3-paraview).
Usage: paraview_check.py --tetfsi BIN --scene data/scenes/smoke_sheets_ci.json [--keep DIR]
       paraview_check.py --scene data/scenes/smoke_sheets.json --out OUTDIR   (checks the output of
       an earlier `tetfsi run SCENE --out OUTDIR` of a scene with the same objects, e.g. the flagship)
"""

import argparse
import array
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
import zlib

OBJECTS = {"fluid": {"point": ["pressure", "smoke", "temperature", "velocity"],
                     "cell": ["smoke", "temperature", "velocity"]},
           "deflector": {"point": ["displacement", "velocity"], "cell": ["subdomain"]},
           "catcher": {"point": ["displacement", "velocity"], "cell": ["subdomain"]}}

# Runs in pvpython: prints one line "PV <json>" per object with what ParaView read at each time.
PVPYTHON = r"""
import json, sys
from paraview.simple import OpenDataFile, GetParaViewVersion, UpdatePipeline
from paraview import servermanager
from vtkmodules.util.vtkConstants import VTK_FLOAT, VTK_DOUBLE
v = GetParaViewVersion()
print("VERSION %d.%d" % (v.major, v.minor))
for name, path in json.loads(sys.argv[1]).items():
    reader = OpenDataFile(path)
    times = list(reader.TimestepValues)
    frames = []
    for t in times:
        UpdatePipeline(time=t, proxy=reader)
        data = servermanager.Fetch(reader)
        if data.IsA("vtkMultiBlockDataSet"):
            data = data.GetBlock(0)
        def fields(d):
            out = {}
            for i in range(d.GetNumberOfArrays()):
                a = d.GetArray(i)
                lo, hi = a.GetRange(-1)
                out[a.GetName()] = {"type": a.GetDataType(), "components": a.GetNumberOfComponents(), "max_norm": hi,
                                    "sum": sum(a.GetComponent(j, c) for j in range(a.GetNumberOfTuples())
                                               for c in range(a.GetNumberOfComponents()))}
            return out
        frames.append({"time": t, "points": data.GetNumberOfPoints(), "cells": data.GetNumberOfCells(),
                       "points_type": data.GetPoints().GetDataType(), "point": fields(data.GetPointData()),
                       "cell": fields(data.GetCellData())})
    print("PV " + json.dumps({"object": name, "times": times, "frames": frames,
                              "float": VTK_FLOAT, "double": VTK_DOUBLE}))
"""


def piece_counts(path):
    """(points, cells) from a .vtu's <Piece> element (the file's head only: the data follow)."""
    with open(path, "rb") as f:
        head = f.read(4096).decode("ascii", errors="replace")
    m = re.search(r'<Piece NumberOfPoints="(\d+)" NumberOfCells="(\d+)"', head)
    return int(m.group(1)), int(m.group(2))


def field_sums(path):
    """{("point"|"cell", name): sum of the values} of a tetfsi .vtu with zlib-compressed raw
    appended Float32 fields (VTK's block header: nb, block size, last size, nb compressed sizes)."""
    with open(path, "rb") as f:
        data = f.read()
    head_end = data.index(b"<AppendedData")
    head = data[:head_end].decode("ascii")
    start = data.index(b"_", head_end) + 1
    sums = {}
    for section, body in re.findall(r"<(PointData|CellData)>(.*?)</(?:PointData|CellData)>", head, re.S):
        for typ, name, offset in re.findall(r'<DataArray type="(\w+)" Name="(\w+)"[^>]* offset="(\d+)"', body):
            at = start + int(offset)
            nb = struct.unpack_from("<Q", data, at)[0]
            sizes = struct.unpack_from(f"<{nb}Q", data, at + 24)
            at += 24 + 8 * nb
            raw = b""
            for size in sizes:
                raw += zlib.decompress(data[at:at + size])
                at += size
            values = array.array({"Float32": "f", "Float64": "d"}[typ], raw)
            total = 0.0
            for v in values:
                total += v
            sums[("point" if section == "PointData" else "cell", name)] = total
    return sums


def run(cmd):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if p.returncode != 0:
        sys.exit(f"FAILED ({p.returncode}): {' '.join(cmd)}\n{p.stdout}")
    return p.stdout


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tetfsi", help="the tetfsi binary (runs --scene); not needed with --out")
    ap.add_argument("--out", help="check this output folder of an earlier run of --scene instead")
    ap.add_argument("--scene", required=True, help="data/scenes/smoke_sheets_ci.json")
    ap.add_argument("--keep", help="work in this folder and keep it")
    args = ap.parse_args()
    pvpython = shutil.which("pvpython")
    if not pvpython:
        print("pvpython not on PATH (apt-get install python3-paraview): skipped")
        return 77
    work = args.keep or tempfile.mkdtemp(prefix="paraview_check_")
    os.makedirs(work, exist_ok=True)
    failures = []

    def expect(ok, what):
        print(("ok   " if ok else "FAIL ") + what)
        if not ok:
            failures.append(what)

    with open(args.scene) as f:
        scene = json.load(f)
    frame_rate = scene["simulation"]["frame_rate"]
    frames = int(round(scene["simulation"]["end_time"] * frame_rate)) + 1
    out = args.out or os.path.join(work, "out")
    if not args.out:
        if not args.tetfsi:
            sys.exit("paraview_check: give --tetfsi BIN or --out OUTDIR")
        run([args.tetfsi, "run", args.scene, "--out", out, "--quiet"])
    pvds = {name: os.path.join(out, name + ".pvd") for name in OBJECTS}
    script = os.path.join(work, "read_pvd.py")
    with open(script, "w") as f:
        f.write(PVPYTHON)
    report = run([pvpython, "--force-offscreen-rendering", script, json.dumps(pvds)])
    version = next((l.split()[1] for l in report.splitlines() if l.startswith("VERSION ")), "?")
    got = {r["object"]: r for r in (json.loads(l[3:]) for l in report.splitlines() if l.startswith("PV "))}
    print(f"ParaView {version} (pvpython) on {out}")
    for name, fields in OBJECTS.items():
        entries = list(ET.parse(pvds[name]).getroot().iter("DataSet"))
        listed = [float(e.get("timestep")) for e in entries]
        r = got.get(name)
        expect(r is not None, f"{name}: pvpython opened {name}.pvd")
        if r is None:
            continue
        expect(len(r["times"]) == frames and all(abs(a - b) <= 1e-12 for a, b in zip(r["times"], listed)),
               f"{name}: ParaView's time values {r['times']} are the .pvd's {listed}")
        expect(all(abs(t - k / frame_rate) <= 1e-9 for k, t in enumerate(r["times"])),
               f"{name}: time values are k / {frame_rate:g} s")
        counts = [piece_counts(os.path.join(out, e.get("file"))) for e in entries]
        seen = [(f["points"], f["cells"]) for f in r["frames"]]
        expect(seen == counts, f"{name}: at each time the points and cells of that time's file: {seen}")
        files = [field_sums(os.path.join(out, e.get("file"))) for e in entries]
        read = [{(d, a): v["sum"] for d in ("point", "cell") for a, v in f[d].items()} for f in r["frames"]]
        expect(read == files, f"{name}: at each time the sum of every field is that time's file's")
        expect(all(files[0][k] != files[-1][k] for k in files[0] if k != ("cell", "subdomain")),
               f"{name}: every field's sum differs between the first and the last frame")
        expect(all(sorted(f["point"]) == fields["point"] and sorted(f["cell"]) == fields["cell"] for f in r["frames"]),
               f"{name}: point fields {fields['point']}, cell fields {fields['cell']}")
        expect(all(a["type"] == r["float"] for f in r["frames"] for d in ("point", "cell") for a in f[d].values()),
               f"{name}: fields are 32-bit floats (export.precision float32)")
        expect(all(f["points_type"] == r["double"] for f in r["frames"]), f"{name}: points are 64-bit floats")
        first, last = r["frames"][0], r["frames"][-1]
        if name != "fluid":
            expect(first["point"]["displacement"]["max_norm"] == 0 and last["point"]["displacement"]["max_norm"] > 1e-4,
                   f"{name}: largest displacement {first['point']['displacement']['max_norm']:.3g} m at t = 0, "
                   f"{last['point']['displacement']['max_norm']:.3g} m at t = {last['time']:g} s")
    if not args.keep:
        shutil.rmtree(work)
    print("PASSED" if not failures else f"{len(failures)} FAILED")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
