#!/usr/bin/python3
"""Makes fixtures/vtk/ with VTK 9.1 (Debian python3-vtk9): one small jittered tet mesh with point,
cell and field arrays of every numeric type (multi-component with component names, a string
field array, NaN and infinities in a field array), written by vtkXMLUnstructuredGridWriter in
every encoding x compressor x header type x byte order, plus a multi-piece .vtu, a .pvtu with
its pieces, and a small polyhedron mesh. Also writes fixtures/vtk/manifest.json: the counts and
per-array checksums (of VTK's own arrays in memory) the tests compare against.

Usage: /usr/bin/python3 scripts/make_vtk_fixtures.py [OUTDIR]   (default fixtures/vtk)
"""
import json
import os
import random
import sys

import vtk
from vtk.util import numpy_support as ns
import numpy as np

OUT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "fixtures", "vtk")


def tet_mesh():
    img = vtk.vtkImageData()
    img.SetDimensions(4, 4, 4)
    img.SetSpacing(0.5, 0.5, 0.5)
    tri = vtk.vtkDataSetTriangleFilter()
    tri.SetInputData(img)
    tri.Update()
    ug = vtk.vtkUnstructuredGrid()
    ug.DeepCopy(tri.GetOutput())
    rng = random.Random(7)
    pts = vtk.vtkPoints()
    pts.SetDataTypeToFloat()
    for i in range(ug.GetNumberOfPoints()):
        x, y, z = ug.GetPoint(i)
        pts.InsertNextPoint(x + rng.uniform(-0.05, 0.05), y + rng.uniform(-0.05, 0.05), z * 1.5)
    ug.SetPoints(pts)
    n, m = ug.GetNumberOfPoints(), ug.GetNumberOfCells()

    temp = vtk.vtkDoubleArray()
    temp.SetName("temperature")
    for i in range(n):
        x, y, z = ug.GetPoint(i)
        temp.InsertNextValue(300.0 + x * x - 3.25 * y + z / 7.0)
    ug.GetPointData().AddArray(temp)
    ug.GetPointData().SetActiveScalars("temperature")

    vel = vtk.vtkFloatArray()
    vel.SetName("velocity")
    vel.SetNumberOfComponents(3)
    for k, c in enumerate(("vx", "vy", "vz")):
        vel.SetComponentName(k, c)
    for i in range(n):
        x, y, z = ug.GetPoint(i)
        vel.InsertNextTuple3(y, -x, 0.1 * z)
    ug.GetPointData().AddArray(vel)
    ug.GetPointData().SetActiveVectors("velocity")

    mat = vtk.vtkUnsignedCharArray()
    mat.SetName("material")
    for i in range(m):
        mat.InsertNextValue((i * 37) % 256)
    ug.GetCellData().AddArray(mat)

    stress = vtk.vtkFloatArray()
    stress.SetName("stress")
    stress.SetNumberOfComponents(2)
    stress.SetComponentName(0, "normal")
    stress.SetComponentName(1, "shear")
    for i in range(m):
        stress.InsertNextTuple2(i * 0.125, -1.0 / (i + 1))
    ug.GetCellData().AddArray(stress)

    # Field data: every numeric type, a few values each, extremes included.
    fd = ug.GetFieldData()
    zoo = [
        (vtk.vtkSignedCharArray, "f_int8", [-128, -1, 0, 1, 127]),
        (vtk.vtkUnsignedCharArray, "f_uint8", [0, 1, 128, 255]),
        (vtk.vtkShortArray, "f_int16", [-32768, -2, 0, 32767]),
        (vtk.vtkUnsignedShortArray, "f_uint16", [0, 1, 65535]),
        (vtk.vtkIntArray, "f_int32", [-2147483648, -5, 0, 2147483647]),
        (vtk.vtkUnsignedIntArray, "f_uint32", [0, 3, 4294967295]),
        (vtk.vtkTypeInt64Array, "f_int64", [-9223372036854775808, -7, 0, 9223372036854775807]),
        (vtk.vtkTypeUInt64Array, "f_uint64", [0, 9, 18446744073709551615]),
        (vtk.vtkFloatArray, "f_float32", [1.5, -0.0, 3.4028234663852886e38, 1.401298464324817e-45]),
        (vtk.vtkDoubleArray, "f_specials", [float("nan"), float("inf"), float("-inf"), 1e-310, -2.5]),
    ]
    for cls, name, vals in zoo:
        a = cls()
        a.SetName(name)
        for v in vals:
            a.InsertNextValue(v)
        fd.AddArray(a)
    pair = vtk.vtkDoubleArray()
    pair.SetName("time_pair")
    pair.SetNumberOfComponents(2)
    pair.InsertNextTuple2(0.25, 0.5)
    pair.InsertNextTuple2(0.75, 1.0)
    fd.AddArray(pair)
    s = vtk.vtkStringArray()
    s.SetName("labels")
    for v in ["inlet", "outlet wall", "", "k\u00e4fer"]:
        s.InsertNextValue(v)
    fd.AddArray(s)
    return ug


def polyhedron_mesh():
    ug = vtk.vtkUnstructuredGrid()
    pts = vtk.vtkPoints()
    pts.SetDataTypeToDouble()
    for p in [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1), (0.5, 0.5, 2)]:
        pts.InsertNextPoint(p)
    ug.SetPoints(pts)
    faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
    stream = vtk.vtkIdList()
    stream.InsertNextId(len(faces))
    for f in faces:
        stream.InsertNextId(len(f))
        for v in f:
            stream.InsertNextId(v)
    ug.InsertNextCell(vtk.VTK_POLYHEDRON, stream)
    ids = vtk.vtkIdList()
    for v in (4, 5, 6, 8):
        ids.InsertNextId(v)
    ug.InsertNextCell(vtk.VTK_TETRA, ids)
    stream2 = vtk.vtkIdList()
    pyr = [[4, 5, 6, 7], [4, 5, 8], [5, 6, 8], [6, 7, 8], [7, 4, 8]]
    stream2.InsertNextId(len(pyr))
    for f in pyr:
        stream2.InsertNextId(len(f))
        for v in f:
            stream2.InsertNextId(v)
    ug.InsertNextCell(vtk.VTK_POLYHEDRON, stream2)
    cid = vtk.vtkIntArray()
    cid.SetName("cell_id")
    for i in range(3):
        cid.InsertNextValue(i)
    ug.GetCellData().AddArray(cid)
    return ug


class Pieces:
    """A piece-aware source: serves cells [k*m/n, (k+1)*m/n) of the mesh for piece k of n."""

    def __init__(self, ug):
        self.ug = ug
        self.f = vtk.vtkProgrammableFilter()
        self.f.SetInputData(ug)
        self.f.SetExecuteMethod(self.execute)

    def execute(self):
        info = self.f.GetOutputInformation(0)
        sddp = vtk.vtkStreamingDemandDrivenPipeline
        k = info.Get(sddp.UPDATE_PIECE_NUMBER())
        n = max(1, info.Get(sddp.UPDATE_NUMBER_OF_PIECES()))
        m = self.ug.GetNumberOfCells()
        ids = vtk.vtkIdList()
        for c in range(k * m // n, (k + 1) * m // n):
            ids.InsertNextId(c)
        ex = vtk.vtkExtractCells()
        ex.SetInputData(self.ug)
        ex.SetCellList(ids)
        ex.Update()
        out = self.f.GetUnstructuredGridOutput()
        out.ShallowCopy(ex.GetOutput())
        out.GetFieldData().ShallowCopy(self.ug.GetFieldData())


def configure(w, mode, comp, header, order, ids):
    {"ascii": w.SetDataModeToAscii, "binary": w.SetDataModeToBinary,
     "appended": w.SetDataModeToAppended, "appended64": w.SetDataModeToAppended}[mode]()
    w.SetEncodeAppendedData(mode == "appended64")
    {"none": w.SetCompressorTypeToNone, "zlib": w.SetCompressorTypeToZLib,
     "lz4": w.SetCompressorTypeToLZ4, "lzma": w.SetCompressorTypeToLZMA}[comp]()
    if header == "h32":
        w.SetHeaderTypeToUInt32()
    else:
        w.SetHeaderTypeToUInt64()
    if order == "le":
        w.SetByteOrderToLittleEndian()
    else:
        w.SetByteOrderToBigEndian()
    if ids == "i32":
        w.SetIdTypeToInt32()
    else:
        w.SetIdTypeToInt64()


def write(ug, name, mode="appended", comp="none", header="h64", order="le", ids="i64"):
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetInputData(ug)
    w.SetFileName(os.path.join(OUT, name))
    configure(w, mode, comp, header, order, ids)
    assert w.Write() == 1, name
    return name


XML_TYPES = {"i1": "Int8", "u1": "UInt8", "i2": "Int16", "u2": "UInt16", "i4": "Int32", "u4": "UInt32",
             "i8": "Int64", "u8": "UInt64", "f4": "Float32", "f8": "Float64"}


def csum(v):
    """Order-sensitive checksum of an array's little-endian bytes (tests/vtu_common.rs computes the
    same): zero-pad to 8 bytes, read u64 words w_i, sum w_i * (2i + 1) mod 2^64."""
    v = np.ascontiguousarray(v)
    b = v.astype(v.dtype.newbyteorder("<")).tobytes()
    b += b"\0" * (-len(b) % 8)
    w = np.frombuffer(b, dtype="<u8")
    k = np.arange(len(w), dtype=np.uint64) * np.uint64(2) + np.uint64(1)
    with np.errstate(over="ignore"):
        return str(int(np.sum(w * k, dtype=np.uint64)))


def checksum(a):
    """Counts, type and checksum of an array as VTK holds it in memory."""
    names = [a.GetComponentName(k) or "" for k in range(a.GetNumberOfComponents())] if any(
        a.GetComponentName(k) for k in range(a.GetNumberOfComponents())) else []
    if a.IsA("vtkStringArray"):
        vals = [a.GetValue(i) for i in range(a.GetNumberOfValues())]
        return {"type": "String", "components": a.GetNumberOfComponents(), "tuples": a.GetNumberOfTuples(),
                "component_names": names, "strings": vals}
    v = ns.vtk_to_numpy(a).reshape(-1)
    return {"type": XML_TYPES[v.dtype.kind + str(v.dtype.itemsize)], "components": a.GetNumberOfComponents(),
            "tuples": a.GetNumberOfTuples(), "component_names": names, "csum": csum(v)}


def describe(ug):
    cells = ug.GetCells()
    conn = ns.vtk_to_numpy(cells.GetConnectivityArray()).astype(np.int64)
    offs = ns.vtk_to_numpy(cells.GetOffsetsArray()).astype(np.int64)
    d = {
        "points": ug.GetNumberOfPoints(),
        "cells": ug.GetNumberOfCells(),
        "points_array": checksum(ug.GetPoints().GetData()),
        "connectivity_csum": csum(conn),
        "offsets_csum": csum(offs),
        "types_csum": csum(ns.vtk_to_numpy(ug.GetCellTypesArray()).astype(np.uint8)),
        "point_data": {},
        "cell_data": {},
        "field_data": {},
    }
    for key, fd in (("point_data", ug.GetPointData()), ("cell_data", ug.GetCellData()), ("field_data", ug.GetFieldData())):
        for i in range(fd.GetNumberOfArrays()):
            a = fd.GetAbstractArray(i)
            d[key][a.GetName()] = checksum(a)
    return d


def main():
    os.makedirs(OUT, exist_ok=True)
    ug = tet_mesh()
    files = []
    files.append(write(ug, "tet_ascii.vtu", mode="ascii"))
    for mode in ("binary", "appended", "appended64"):
        for comp in ("none", "zlib", "lz4", "lzma"):
            for header in ("h32", "h64"):
                for order in ("le", "be"):
                    # Int32 ids with 32-bit headers, Int64 with 64-bit: both id types covered.
                    ids = "i32" if header == "h32" else "i64"
                    files.append(write(ug, f"tet_{mode}_{comp}_{header}_{order}.vtu", mode, comp, header, order, ids))

    src = Pieces(ug)
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetInputConnection(src.f.GetOutputPort())
    w.SetFileName(os.path.join(OUT, "tet_3pieces.vtu"))
    w.SetNumberOfPieces(3)
    configure(w, "appended", "zlib", "h64", "le", "i64")
    assert w.Write() == 1
    files.append("tet_3pieces.vtu")

    pw = vtk.vtkXMLPUnstructuredGridWriter()
    pw.SetInputConnection(src.f.GetOutputPort())
    pw.SetFileName(os.path.join(OUT, "tet_parallel.pvtu"))
    pw.SetNumberOfPieces(3)
    pw.SetStartPiece(0)
    pw.SetEndPiece(2)
    pw.SetUseSubdirectory(True)
    configure(pw, "appended", "lz4", "h32", "le", "i32")
    assert pw.Write() == 1
    files.append("tet_parallel.pvtu")

    poly = polyhedron_mesh()
    write(poly, "polyhedra_ascii.vtu", mode="ascii")
    write(poly, "polyhedra_binary_zlib.vtu", mode="binary", comp="zlib")

    manifest = {"tet": describe(ug), "polyhedra": describe(poly),
                "tet_files": files, "polyhedra_files": ["polyhedra_ascii.vtu", "polyhedra_binary_zlib.vtu"]}
    with open(os.path.join(OUT, "manifest.json"), "w") as fh:
        json.dump(manifest, fh, indent=1, sort_keys=True)
        fh.write("\n")


if __name__ == "__main__":
    main()
