#!/usr/bin/python3
"""Writes, with VTK's own writers, a small mixed mesh holding what ParaView files carry and the
tests had not seen: vtkBitArray point and field data, vtkStringArray point/cell/field data,
vtkIdTypeArray (vtkOriginalIndices), vtkGhostType, a 9-component tensor with component names,
an information key (UNITS_LABEL), an unused point, and a triangle and a vertex beside the tets.

Usage: newuser_paraview_like.py OUTDIR
Writes OUTDIR/pv_<mode>.vtu for every XML data mode and compressor (ascii, binary none/zlib,
appended raw none/zlib/lz4/lzma, appended base64) and OUTDIR/pv_{42,51}_{ascii,binary}.vtk.
"""
import os
import sys

import vtk

out = sys.argv[1]
pts = vtk.vtkPoints()
P = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1),
     (0.5, 0.5, 0.5), (5, 5, 5)]  # the last point is used by the vertex cell only
for p in P:
    pts.InsertNextPoint(p)
g = vtk.vtkUnstructuredGrid()
g.SetPoints(pts)
for f in [(0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]:
    g.InsertNextCell(vtk.VTK_TETRA, 4, [f[0], f[1], f[2], 8])
    g.InsertNextCell(vtk.VTK_TETRA, 4, [f[0], f[2], f[3], 8])
g.InsertNextCell(vtk.VTK_TRIANGLE, 3, [0, 1, 2])
g.InsertNextCell(vtk.VTK_VERTEX, 1, [9])
nc, npt = g.GetNumberOfCells(), g.GetNumberOfPoints()


def arr(cls, name, comps, n, f):
    a = cls()
    a.SetName(name)
    a.SetNumberOfComponents(comps)
    a.SetNumberOfTuples(n)
    for i in range(n):
        for c in range(comps):
            a.SetComponent(i, c, f(i, c))
    return a


def bits(name, n, f):
    a = vtk.vtkBitArray()
    a.SetName(name)
    a.SetNumberOfTuples(n)
    for i in range(n):
        a.SetValue(i, f(i))
    return a


def strings(name, n, f):
    a = vtk.vtkStringArray()
    a.SetName(name)
    a.SetNumberOfTuples(n)
    for i in range(n):
        a.SetValue(i, f(i))
    return a


pd, cd, fd = g.GetPointData(), g.GetCellData(), g.GetFieldData()
temp = arr(vtk.vtkFloatArray, "temp", 1, npt, lambda i, c: i * 1.5)
temp.GetInformation().Set(vtk.vtkDataArray.UNITS_LABEL(), "K")
pd.AddArray(temp)
pd.SetScalars(temp)
pd.AddArray(arr(vtk.vtkDoubleArray, "vel", 3, npt, lambda i, c: i + c * 0.1))
pd.AddArray(arr(vtk.vtkIdTypeArray, "vtkOriginalIndices", 1, npt, lambda i, c: i))
pd.AddArray(bits("flag", npt, lambda i: (i * 5 + 1) % 3 % 2))
pd.AddArray(strings("label", npt, lambda i: "pt %d <&>" % i))
cd.AddArray(arr(vtk.vtkUnsignedCharArray, "vtkGhostType", 1, nc, lambda i, c: 1 if i == 0 else 0))
cd.AddArray(arr(vtk.vtkIdTypeArray, "vtkOriginalCellIds", 1, nc, lambda i, c: i))
stress = arr(vtk.vtkDoubleArray, "stress", 9, nc, lambda i, c: i * 10 + c)
stress.SetComponentName(0, "xx")
stress.SetComponentName(4, "yy")
cd.AddArray(stress)
cd.AddArray(bits("cbits", nc, lambda i: 1 if i in (0, 8, 9, 13) else 0))
cd.AddArray(strings("cname", nc, lambda i: "c%d" % i))
fd.AddArray(strings("units", 2, lambda i: ["m", "s s"][i]))
fd.AddArray(arr(vtk.vtkDoubleArray, "TimeValue", 1, 1, lambda i, c: 0.25))
fd.AddArray(bits("fbits", 11, lambda i: (i * 7) % 2))

modes = [("ascii", 0, None, False), ("binary_none", 1, None, False),
         ("binary_zlib", 1, vtk.vtkZLibDataCompressor, False),
         ("appended_none", 2, None, False), ("appended_zlib", 2, vtk.vtkZLibDataCompressor, False),
         ("appended_lz4", 2, vtk.vtkLZ4DataCompressor, False),
         ("appended_lzma", 2, vtk.vtkLZMADataCompressor, False),
         ("appended_base64", 2, vtk.vtkZLibDataCompressor, True)]
for name, mode, comp, b64 in modes:
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetInputData(g)
    w.SetFileName(os.path.join(out, "pv_%s.vtu" % name))
    w.SetDataMode(mode)
    w.SetEncodeAppendedData(1 if b64 else 0)
    if comp is None:
        w.SetCompressorTypeToNone()
    else:
        w.SetCompressor(comp())
    assert w.Write() == 1, name
for ver in (42, 51):
    for binary in (False, True):
        w = vtk.vtkUnstructuredGridWriter()
        w.SetInputData(g)
        w.SetFileName(os.path.join(out, "pv_%d_%s.vtk" % (ver, "binary" if binary else "ascii")))
        if ver == 42:
            w.SetFileVersion(42)
        if binary:
            w.SetFileTypeToBinary()
        assert w.Write() == 1
