#!/usr/bin/env python3
"""Reads a .vtu (or every file of a .pvd) with VTK's own reader and prints, per file,
"points cells field:components ..." so that C++ tests can compare with what they wrote.
With --sums, each field (and the points) is followed by "=" and the sum of its values as VTK
decoded them (17 significant digits), so two files holding the same data print the same line.
Exits 1 with a message if VTK cannot read the file."""
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader


def array_sum(a) -> str:
    total = 0.0
    for i in range(a.GetNumberOfTuples()):
        for c in range(a.GetNumberOfComponents()):
            total += a.GetComponent(i, c)
    return f"={total:.17g}"


def describe(path: Path, sums: bool = False) -> str:
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    if reader.GetErrorCode() != 0 or grid is None:
        raise RuntimeError(f"VTK could not read {path}")
    parts = [str(grid.GetNumberOfPoints()), str(grid.GetNumberOfCells())]
    if sums and grid.GetPoints() is not None:
        parts.append("points" + array_sum(grid.GetPoints().GetData()))
    for data, tag in ((grid.GetPointData(), "p"), (grid.GetCellData(), "c")):
        for i in range(data.GetNumberOfArrays()):
            a = data.GetArray(i)
            parts.append(f"{tag}:{a.GetName()}:{a.GetNumberOfComponents()}" + (array_sum(a) if sums else ""))
    return " ".join(parts)


def main() -> int:
    args = [a for a in sys.argv[1:] if a != "--sums"]
    sums = len(args) != len(sys.argv) - 1
    path = Path(args[0])
    try:
        if path.suffix == ".pvd":
            root = ET.parse(path).getroot()
            for ds in root.iter("DataSet"):
                print(ds.get("timestep"), describe(path.parent / ds.get("file"), sums))
        else:
            print(describe(path, sums))
    except Exception as e:  # noqa: BLE001 - report any reader failure to the calling test
        print(f"error: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
