#!/usr/bin/python3
"""Regenerates fixtures/legacy/ with VTK 9.1 (python3-vtk9): one mixed mesh carrying every
attribute kind, written as legacy 4.2 and 5.1, ASCII and binary (mixed_{42,51}_{ascii,binary}.vtk),
plus checksums.json with what VTK itself reads back from each file (counts and per-array sums),
which tests/legacy_fixtures.rs compares with tetkit's reader. handmade_*.vtk are written by hand
(FIELD before POINTS, METADATA with INFORMATION keys, vtkIdType, TENSORS6, COLOR_SCALARS, an inline
LOOKUP_TABLE, a bit array) and checked against VTK here as well."""
import json
import math
import os
import sys

import vtk
from vtk_legacy_summary import summarize
from vtk.util.numpy_support import numpy_to_vtk, vtk_to_numpy
import numpy as np

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fixtures", "legacy")


def mixed_mesh():
    rng = np.random.default_rng(7)
    ball = vtk.vtkPoints()
    ball.SetData(numpy_to_vtk(rng.uniform(-1, 1, (40, 3)).astype(np.float32), deep=1))
    cloud = vtk.vtkPolyData()
    cloud.SetPoints(ball)
    d = vtk.vtkDelaunay3D()
    d.SetInputData(cloud)
    d.Update()
    g = vtk.vtkUnstructuredGrid()
    g.DeepCopy(d.GetOutput())
    pts = g.GetPoints()
    base = pts.GetNumberOfPoints()
    # A unit-ish block of extra cells beside the ball: hexahedron, wedge, pyramid, quadratic
    # tetra, triangle, polyhedron (a tet given as faces).
    extra = [(x + 2, y, z) for z in (0, 1) for (x, y) in ((0, 0), (1, 0), (1, 1), (0, 1))]
    extra += [(3.5, 0.5, 0.5), (2.5, 0.5, 1.5)]
    for p in extra:
        pts.InsertNextPoint(p)
    b = base
    g.InsertNextCell(vtk.VTK_HEXAHEDRON, 8, [b + i for i in range(8)])
    g.InsertNextCell(vtk.VTK_WEDGE, 6, [b + 1, b + 2, b + 8, b + 5, b + 6, b + 8])
    g.InsertNextCell(vtk.VTK_PYRAMID, 5, [b + 4, b + 5, b + 6, b + 7, b + 9])
    q = [b + 4, b + 5, b + 7, b + 9]
    for (i, j) in ((0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)):
        pa, pb = pts.GetPoint(q[i]), pts.GetPoint(q[j])
        q.append(pts.InsertNextPoint([(pa[k] + pb[k]) / 2 for k in range(3)]))
    g.InsertNextCell(vtk.VTK_QUADRATIC_TETRA, 10, q)
    g.InsertNextCell(vtk.VTK_TRIANGLE, 3, [b + 0, b + 1, b + 2])
    a, c, e, f = b + 1, b + 2, b + 6, b + 8
    faces = [4, 3, a, c, e, 3, a, c, f, 3, a, e, f, 3, c, e, f]
    ids = vtk.vtkIdList()
    for x in faces:
        ids.InsertNextId(x)
    g.InsertNextCell(vtk.VTK_POLYHEDRON, ids)

    n, c = g.GetNumberOfPoints(), g.GetNumberOfCells()
    pd, cd, fd = g.GetPointData(), g.GetCellData(), g.GetFieldData()

    def arr(values, name, comps=1):
        a = numpy_to_vtk(np.ascontiguousarray(values), deep=1)
        a.SetNumberOfComponents(comps)
        a.SetName(name)
        return a

    temp = arr(rng.random(n).astype(np.float32), "temperature")
    # No NaN here: VTK 9.1 cannot read "nan" back from its own ASCII files.
    lut = vtk.vtkLookupTable()
    lut.SetNumberOfTableValues(4)
    lut.Build()
    temp.SetLookupTable(lut)
    pd.SetScalars(temp)
    vel = arr(rng.standard_normal((n, 3)), "velocity", 3)
    for k, nm in enumerate(("u", "v w", "")):
        if nm:
            vel.SetComponentName(k, nm)
    pd.SetVectors(vel)
    pd.SetNormals(arr(rng.random((n, 3)).astype(np.float32), "normals", 3))
    pd.SetTCoords(arr(rng.random((n, 2)), "uv", 2))
    pd.SetTensors(arr(rng.random((n, 9)), "stress", 9))
    gid = vtk.vtkIdTypeArray()
    gid.SetName("global ids")
    for i in range(n):
        gid.InsertNextValue(1000 + i)
    pd.SetGlobalIds(gid)
    for dt, name in ((np.int8, "i8"), (np.uint8, "u8"), (np.int16, "i16"), (np.uint16, "u16"),
                     (np.int32, "i32"), (np.uint32, "u32"), (np.int64, "i64"), (np.uint64, "u64"),
                     (np.float64, "f64")):
        info = np.iinfo(dt) if dt != np.float64 else None
        v = (rng.integers(int(info.min) // 2, int(info.max) // 2, n, dtype=np.int64 if dt != np.uint64 else np.uint64).astype(dt)
             if info else rng.standard_normal(n) * 1e300)
        if info:
            v[0] = info.min
            v[1] = info.max
        pd.AddArray(arr(v, name))
    pd.AddArray(arr(rng.integers(0, 255, (n, 4)).astype(np.uint8), "rgba", 4))

    region = arr(np.arange(c, dtype=np.int32) % 3, "region")
    cd.SetScalars(region)
    ped = arr(np.arange(c, dtype=np.int64) * 10, "pedigree")
    cd.SetPedigreeIds(ped)
    quality = arr(rng.random(c), "quality")
    # An INFORMATION key (VTK 9.1 cannot read back string keys, so a double vector one).
    quality.GetInformation().Set(vtk.vtkDataArray.L2_NORM_RANGE(), [0.0, 1.0], 2)
    cd.AddArray(quality)
    cd.AddArray(arr(rng.random((c, 6)).astype(np.float32), "sym tensor", 6))

    fd.AddArray(arr(np.array([0.5, 1.5, 2.5]), "time"))
    fd.AddArray(arr(np.array([7], dtype=np.int32), "step"))
    s = vtk.vtkStringArray()
    s.SetName("notes")
    for x in ("made by VTK", "100% legacy", ""):
        s.InsertNextValue(x)
    fd.AddArray(s)
    return g


HANDMADE_ASCII = """# vtk DataFile Version 5.1
hand-written: FIELD before POINTS, METADATA, vtkIdType, TENSORS6, COLOR_SCALARS, LOOKUP_TABLE, bit
ASCII
DATASET UNSTRUCTURED_GRID
FIELD FieldData 2
ids 1 3 vtkIdType
5 6 7
labels 1 2 string
first%20label
second
POINTS 5 double
0 0 0	1 0 0 0 1 0
0 0 1 1 1 1
METADATA
COMPONENT_NAMES
X
Y
Z

CELLS 3 8
OFFSETS vtktypeint64
0 4 8
CONNECTIVITY vtktypeint64
0 1 2 3 1 2 3 4
CELL_TYPES 2
10
10

CELL_DATA 2
SCALARS mat int 1
LOOKUP_TABLE materials
1 2
LOOKUP_TABLE materials 2
1 0 0 1
0 0 1 0.5
TENSORS6 sym double
1 2 3 4 5 6
6 5 4 3 2 1
POINT_DATA 5
COLOR_SCALARS colors 3
1 0 0 0 1 0 0 0 1 1 1 1 0.2 0.4 0.6
VECTORS disp float
0.5 0 0 0 0.5 0 0 0 0.5 1 1 1 -1 -1 -1
METADATA
COMPONENT_NAMES
dx
dy
dz
INFORMATION 1
NAME L2_NORM_RANGE LOCATION vtkDataArray
DATA 2 0 1.7320508

FIELD FieldData 2
flags 1 5 bit
1 0 1 1 0
count 2 5 unsigned_short
1 2 3 4 5 6 7 8 9 10
"""


def handmade_binary():
    """A 4.2 binary file built byte by byte: vtkIdType (4 bytes each), bit (packed), strings
    (length-prefixed), unsigned_long, a polyhedron, a field before POINTS."""
    import struct
    be = lambda fmt, *v: struct.pack(">" + fmt, *v)
    out = [b"# vtk DataFile Version 4.2\nhand-written binary 4.2\nBINARY\n",
           b"DATASET UNSTRUCTURED_GRID\nFIELD FieldData 2\nids 1 3 vtkIdType\n",
           be("3i", 5, 6, 7), b"\nnames 1 2 string\n",
           bytes([0xC0 | 5]) + b"a b c" + be("H", 0x8000 | 70) + b"x" * 70, b"\n",
           b"POINTS 5 float\n", be("15f", 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1), b"\n"]
    faces = [4, 3, 1, 2, 3, 3, 1, 2, 4, 3, 1, 3, 4, 3, 2, 3, 4]
    cells = [4, 0, 1, 2, 3, len(faces)] + faces
    out += [b"CELLS 2 %d\n" % len(cells), be("%di" % len(cells), *cells), b"\n",
            b"CELL_TYPES 2\n", be("2i", 10, 42), b"\n",
            b"CELL_DATA 2\nFIELD FieldData 1\nbig 1 2 unsigned_long\n",
            be("2Q", 2 ** 64 - 1, 12345), b"\n",
            b"POINT_DATA 5\nSCALARS bits bit\nLOOKUP_TABLE default\n", bytes([0b10110000]), b"\n",
            b"GLOBAL_IDS gid vtkIdType\n", be("5i", 10, 11, 12, 13, 14), b"\n"]
    return b"".join(out)


def main():
    os.makedirs(OUT, exist_ok=True)
    g = mixed_mesh()
    sums = {}
    for ver in (42, 51):
        for binary in (False, True):
            name = f"mixed_{ver}_{'binary' if binary else 'ascii'}.vtk"
            w = vtk.vtkUnstructuredGridWriter()
            w.SetInputData(g)
            w.SetFileName(os.path.join(OUT, name))
            w.SetFileVersion(ver)
            if binary:
                w.SetFileTypeToBinary()
            if not w.Write():
                sys.exit(f"VTK failed to write {name}")
    with open(os.path.join(OUT, "handmade_51_ascii.vtk"), "w") as f:
        f.write(HANDMADE_ASCII)
    with open(os.path.join(OUT, "handmade_42_binary.vtk"), "wb") as f:
        f.write(handmade_binary())
    for name in sorted(os.listdir(OUT)):
        if name.endswith(".vtk"):
            sums[name] = summarize(os.path.join(OUT, name))
    with open(os.path.join(OUT, "checksums.json"), "w") as f:
        json.dump(sums, f, indent=1, sort_keys=True)
    for name, s in sums.items():
        print(name, s["points"], "points", s["cells"], "cells")


if __name__ == "__main__":
    main()
