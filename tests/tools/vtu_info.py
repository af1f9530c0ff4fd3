#!/usr/bin/env python3
"""Reads a .vtu (or every file of a .pvd) with VTK's own reader and prints, per file,
"points cells field:components ..." so that C++ tests can compare with what they wrote.
Exits 1 with a message if VTK cannot read the file."""
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader


def describe(path: Path) -> str:
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    if reader.GetErrorCode() != 0 or grid is None:
        raise RuntimeError(f"VTK could not read {path}")
    parts = [str(grid.GetNumberOfPoints()), str(grid.GetNumberOfCells())]
    for data, tag in ((grid.GetPointData(), "p"), (grid.GetCellData(), "c")):
        for i in range(data.GetNumberOfArrays()):
            a = data.GetArray(i)
            parts.append(f"{tag}:{a.GetName()}:{a.GetNumberOfComponents()}")
    return " ".join(parts)


def main() -> int:
    path = Path(sys.argv[1])
    try:
        if path.suffix == ".pvd":
            root = ET.parse(path).getroot()
            for ds in root.iter("DataSet"):
                print(ds.get("timestep"), describe(path.parent / ds.get("file")))
        else:
            print(describe(path))
    except Exception as e:  # noqa: BLE001 - report any reader failure to the calling test
        print(f"error: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
