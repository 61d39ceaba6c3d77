#!/usr/bin/python3
"""Reads a mesh with VTK 9.1 and prints, as JSON, what Rust tests compare tetkit's reading against.

Usage: vtk_check.py FILE... [--volume]

With one FILE it prints one JSON object; with several, a JSON list of them (one VTK start-up for
many files). A file VTK cannot read gives {"file": ..., "error": "..."} in a list, and exit
status 2 alone.

FILE is .vtu, .pvtu or legacy .vtk. The JSON holds counts, cell type counts, bounds, and for the
points, the cell arrays (types, offsets, connectivity) and every point/cell/field array: its name,
type (VTK XML names: Int8 .. Float64, String), components, component names, tuples and checksums:
  crc32   zlib CRC-32 of the values' bytes in their own type, little endian (strings: UTF-8, each
          followed by a NUL), the same bytes `formats::ArrayData::native_bytes` gives;
  sum     for integer arrays the exact sum, as a decimal string (no overflow, no rounding);
  VTK `bit` arrays are reported as UInt8 0/1 values (with "vtk_type": "bit"), as tetkit keeps them.
  fsum, fsum2  float64 sum and sum of squares of all values (non-finite values are skipped and
          counted in `nonfinite`), for a tolerance comparison where bits may legitimately differ.
--volume adds `volume`: the sum of the signed volumes vtkCellSizeFilter gives for 3-D cells (VTK's
own parametric wedge counts as negative), `abs_volume`, the sum of their absolute values,
`volume_cells`, how many 3-D cells it summed, `min_cell_volume`, and `tri_volume`: the volume of
VTK's own tetrahedralization (vtkDataSetTriangleFilter), which also covers the cells
vtkCellSizeFilter measures as 0 (triquadratic hexahedra).
Exit status 2 with a message on stderr when VTK cannot read the file.
"""
import json
import math
import sys
import zlib

import vtk
from vtk.util import numpy_support
import numpy as np

# vtkType ids -> VTK XML type names (VTK_LONG is 64-bit on Linux, as VTK writes it).
TYPE_NAMES = {
    2: "Int8", 15: "Int8", 3: "UInt8", 4: "Int16", 5: "UInt16", 6: "Int32", 7: "UInt32",
    8: "Int64", 9: "UInt64", 12: "Int64", 16: "Int64", 17: "UInt64", 10: "Float32",
    11: "Float64", 13: "String",
}
NUMPY_TYPES = {
    "Int8": "<i1", "UInt8": "<u1", "Int16": "<i2", "UInt16": "<u2", "Int32": "<i4",
    "UInt32": "<u4", "Int64": "<i8", "UInt64": "<u8", "Float32": "<f4", "Float64": "<f8",
}


class CheckError(Exception):
    pass


def fail(msg):
    raise CheckError(msg)


def jfloat(x):
    """JSON has no NaN/inf: those become strings."""
    x = float(x)
    return x if math.isfinite(x) else str(x)


def numeric_summary(values, type_name):
    """Checksums of a flat numpy array, interpreted as `type_name`."""
    a = np.ascontiguousarray(values, dtype=NUMPY_TYPES[type_name]).ravel()
    out = {"values": int(a.size), "crc32": zlib.crc32(a.tobytes()) & 0xFFFFFFFF}
    if type_name.startswith("Float"):
        f = a.astype(np.float64)
        finite = np.isfinite(f)
        g = f[finite]
        out["nonfinite"] = int(a.size - int(finite.sum()))
        out["fsum"] = jfloat(g.sum()) if g.size else 0.0
        out["fsum2"] = jfloat((g * g).sum()) if g.size else 0.0
    else:
        out["sum"] = str(sum(int(v) for v in a.tolist()))
        f = a.astype(np.float64)
        out["fsum"] = jfloat(f.sum())
        out["fsum2"] = jfloat((f * f).sum())
    return out


def array_summary(arr):
    name = arr.GetName() or ""
    ncomp = arr.GetNumberOfComponents()
    tid = arr.GetDataType()
    if tid == vtk.VTK_BIT:
        # tetkit keeps legacy `bit` arrays as UInt8 0/1 values; report them the same way.
        values = np.array([arr.GetValue(i) for i in range(arr.GetNumberOfValues())], dtype="<u1")
        out = {
            "name": name,
            "type": "UInt8",
            "vtk_type": "bit",
            "components": ncomp,
            "component_names": [],
            "tuples": arr.GetNumberOfTuples(),
        }
        out.update(numeric_summary(values, "UInt8"))
        return out
    type_name = TYPE_NAMES.get(tid)
    if type_name is None:
        fail("array '%s' has VTK type %d (%s), which tetkit has no name for"
             % (name, tid, arr.GetDataTypeAsString()))
    comp_names = []
    if arr.HasAComponentName():
        comp_names = [arr.GetComponentName(i) or "" for i in range(ncomp)]
    out = {
        "name": name,
        "type": type_name,
        "components": ncomp,
        "component_names": comp_names,
        "tuples": arr.GetNumberOfTuples(),
    }
    if type_name == "String":
        data = b"".join(arr.GetValue(i).encode("utf-8") + b"\0" for i in range(arr.GetNumberOfValues()))
        out.update({"values": arr.GetNumberOfValues(), "crc32": zlib.crc32(data) & 0xFFFFFFFF})
    else:
        out.update(numeric_summary(numpy_support.vtk_to_numpy(arr), type_name))
    return out


def field_summary(fd):
    return [array_summary(fd.GetAbstractArray(i)) for i in range(fd.GetNumberOfArrays())]


def read(path):
    lower = path.lower()
    if lower.endswith(".pvtu"):
        r = vtk.vtkXMLPUnstructuredGridReader()
    elif lower.endswith(".vtu"):
        r = vtk.vtkXMLUnstructuredGridReader()
    elif lower.endswith(".vtk"):
        r = vtk.vtkUnstructuredGridReader()
        # Without these VTK keeps only the first array of each kind.
        r.ReadAllScalarsOn()
        r.ReadAllVectorsOn()
        r.ReadAllNormalsOn()
        r.ReadAllTensorsOn()
        r.ReadAllColorScalarsOn()
        r.ReadAllTCoordsOn()
        r.ReadAllFieldsOn()
    else:
        fail("%s: not .vtu, .pvtu or .vtk" % path)
    vtk.vtkLogger.SetStderrVerbosity(vtk.vtkLogger.VERBOSITY_OFF)
    errors = vtk.vtkStringOutputWindow()
    vtk.vtkOutputWindow.SetInstance(errors)
    r.SetFileName(path)
    r.Update()
    text = errors.GetOutput()
    if "ERROR" in text:
        fail("%s: VTK reported errors:\n%s" % (path, text))
    if hasattr(r, "GetErrorCode") and r.GetErrorCode() != 0:
        fail("%s: VTK error code %d" % (path, r.GetErrorCode()))
    grid = r.GetOutput()
    if grid is None:
        fail("%s: VTK produced no unstructured grid" % path)
    return grid


def check(path, volume):
    grid = read(path)
    n_points = grid.GetNumberOfPoints()
    n_cells = grid.GetNumberOfCells()
    out = {"file": path, "points": n_points, "cells": n_cells}

    pts = grid.GetPoints()
    if pts is not None and n_points > 0:
        out["points_array"] = array_summary(pts.GetData())
        out["bounds"] = [jfloat(b) for b in grid.GetBounds()]
    else:
        out["points_array"] = None
        out["bounds"] = None

    types = {}
    if n_cells > 0:
        ct = numpy_support.vtk_to_numpy(grid.GetCellTypesArray())
        for t, n in zip(*np.unique(ct, return_counts=True)):
            types[str(int(t))] = int(n)
        out["types"] = numeric_summary(ct, "UInt8")
        cells = grid.GetCells()
        out["offsets"] = numeric_summary(numpy_support.vtk_to_numpy(cells.GetOffsetsArray()), "Int64")
        out["connectivity"] = numeric_summary(
            numpy_support.vtk_to_numpy(cells.GetConnectivityArray()), "Int64")
    else:
        out["types"] = numeric_summary(np.zeros(0), "UInt8")
        out["offsets"] = numeric_summary(np.zeros(1), "Int64")
        out["connectivity"] = numeric_summary(np.zeros(0), "Int64")
    out["cell_types"] = types
    faces = grid.GetFaces()
    out["polyhedron_faces"] = (numeric_summary(numpy_support.vtk_to_numpy(faces), "Int64")
                               if faces is not None and faces.GetNumberOfValues() > 0 else None)

    out["point_data"] = field_summary(grid.GetPointData())
    out["cell_data"] = field_summary(grid.GetCellData())
    out["field_data"] = field_summary(grid.GetFieldData())

    if volume:
        f = vtk.vtkCellSizeFilter()
        f.SetInputData(grid)
        f.ComputeVertexCountOff()
        f.ComputeLengthOff()
        f.ComputeAreaOff()
        f.ComputeVolumeOn()
        f.ComputeSumOff()
        f.Update()
        vols = numpy_support.vtk_to_numpy(f.GetOutput().GetCellData().GetArray("Volume"))
        ct = numpy_support.vtk_to_numpy(grid.GetCellTypesArray()) if n_cells else np.zeros(0)
        solid = np.zeros(len(ct), dtype=bool)
        for t in np.unique(ct):
            first = int(np.argmax(ct == t))
            if grid.GetCell(first).GetCellDimension() == 3:
                solid |= ct == t
        out["volume"] = jfloat(vols[solid].sum()) if solid.any() else 0.0
        out["abs_volume"] = jfloat(np.abs(vols[solid]).sum()) if solid.any() else 0.0
        out["volume_cells"] = int(solid.sum())
        out["min_cell_volume"] = jfloat(vols[solid].min()) if solid.any() else None
        # VTK's own tetrahedralization, for cells vtkCellSizeFilter gives 0 (triquadratic ones).
        t = vtk.vtkDataSetTriangleFilter()
        t.SetInputData(grid)
        t.TetrahedraOnlyOn()
        t.Update()
        f = vtk.vtkCellSizeFilter()
        f.SetInputData(t.GetOutput())
        f.ComputeVertexCountOff()
        f.ComputeLengthOff()
        f.ComputeAreaOff()
        f.ComputeVolumeOn()
        f.Update()
        tv = f.GetOutput().GetCellData().GetArray("Volume")
        out["tri_volume"] = jfloat(np.abs(numpy_support.vtk_to_numpy(tv)).sum()) if tv else 0.0
    return out


def main():
    args = sys.argv[1:]
    volume = "--volume" in args
    files = [a for a in args if not a.startswith("--")]
    if not files:
        sys.stderr.write("usage: vtk_check.py FILE... [--volume]\n")
        sys.exit(2)
    if len(files) == 1:
        try:
            out = check(files[0], volume)
        except CheckError as e:
            sys.stderr.write("vtk_check.py: %s\n" % e)
            sys.exit(2)
    else:
        out = []
        for path in files:
            try:
                out.append(check(path, volume))
            except CheckError as e:
                out.append({"file": path, "error": str(e)})
    json.dump(out, sys.stdout, indent=1, allow_nan=False)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
