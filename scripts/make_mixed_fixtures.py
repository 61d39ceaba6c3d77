#!/usr/bin/python3
"""Writes fixtures/mixed/ with VTK 9.1: a mixed-cell mesh and a quadratic-tet mesh.

mixed.vtu / mixed.vtk (legacy 5.1 ascii) / mixed_42.vtk (legacy 4.2 binary): two blocks.
  Block A, a 4 x 3 x 2 grid of unit cubes, conforming: columns of hexahedra, voxels, wedge pairs
  (VTK-positive wedges), six-pyramid stars around a cube's centre, and polyhedra (cubes written as
  VTK_POLYHEDRON); its outer faces carry boundary quads.
  Block B, 2 x 2 x 2 cubes cut into 6 tets each (Kuhn), apart from A (x >= 5); its outer faces
  carry boundary triangles. A few lines and vertices are added as well.
  Point data: temperature (Float64), velocity (Float32 x3, component names), node_label (Int32).
  Cell data: material (Int32), cell_weight (Float64), flags (UInt8). Field data: a string array and
  a Float64 time value.
prisms.vtu: two stacked pentagonal prisms, two stacked hexagonal prisms and two triquadratic
  hexahedra sharing a face (27 nodes each, on a 0.5 lattice), with a point and a cell array.
quadratic_tets.vtu: a 3 x 3 x 3 cube grid cut into 6 tets each, each tet made a VTK_QUADRATIC_TETRA
  by shared mid-edge nodes (straight edges), with a quadratic point field and a cell id array.
Faces are planar so that any triangulation has the same volume as VTK's.
"""
import os
import sys

import vtk

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fixtures", "mixed")


class Builder:
    def __init__(self):
        self.pts = []
        self.index = {}
        self.cells = []  # (type, ids) or (POLYHEDRON, ids, faces)

    def point(self, p):
        key = tuple(round(x, 9) for x in p)
        if key not in self.index:
            self.index[key] = len(self.pts)
            self.pts.append(p)
        return self.index[key]

    def cube(self, x, y, z, s=1.0):
        c = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
        return [self.point((x + s * a, y + s * b, z + s * d)) for a, b, d in c]


HEX_FACES = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
KUHN = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]]


def kuhn_tets(b, x, y, z):
    """Six tets of the cube at (x, y, z): monotone lattice paths from its 000 to its 111 corner."""
    out = []
    for path in KUHN:
        c = [x, y, z]
        t = [b.point(tuple(c))]
        for axis in path:
            c[axis] += 1
            t.append(b.point(tuple(c)))
        out.append(t)
    return out


def tet_volume(p):
    u = [p[1][k] - p[0][k] for k in range(3)]
    v = [p[2][k] - p[0][k] for k in range(3)]
    w = [p[3][k] - p[0][k] for k in range(3)]
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0]))


def positive(b, t):
    p = [b.pts[i] for i in t]
    return t if tet_volume(p) > 0 else [t[0], t[1], t[3], t[2]]


def mixed():
    b = Builder()
    material = []
    nx, ny, nz = 4, 3, 2
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                h = b.cube(i, j, k)
                kind = (i + 2 * j) % 5
                if kind == 0:
                    b.cells.append((vtk.VTK_HEXAHEDRON, h))
                    material.append(1)
                elif kind == 1:
                    b.cells.append((vtk.VTK_VOXEL, [h[0], h[1], h[3], h[2], h[4], h[5], h[7], h[6]]))
                    material.append(2)
                elif kind == 2:
                    # VTK's positive wedge: (0, 1, 2) clockwise seen from (3, 4, 5).
                    b.cells.append((vtk.VTK_WEDGE, [h[0], h[2], h[1], h[4], h[6], h[5]]))
                    b.cells.append((vtk.VTK_WEDGE, [h[0], h[3], h[2], h[4], h[7], h[6]]))
                    material += [3, 3]
                elif kind == 3:
                    c = b.point((i + 0.5, j + 0.5, k + 0.5))
                    # Each face as a base, counter-clockwise seen from the apex (VTK-positive).
                    for f in HEX_FACES:
                        b.cells.append((vtk.VTK_PYRAMID, [h[f[0]], h[f[3]], h[f[2]], h[f[1]], c]))
                        material.append(4)
                else:
                    faces = [[h[l] for l in f] for f in HEX_FACES]
                    b.cells.append((vtk.VTK_POLYHEDRON, h, faces))
                    material.append(5)
    # Boundary quads of block A (outward faces of the box [0,4]x[0,3]x[0,2]).
    for j in range(ny):
        for i in range(nx):
            for z in (0, nz):
                q = [b.point((i, j, z)), b.point((i + 1, j, z)), b.point((i + 1, j + 1, z)),
                     b.point((i, j + 1, z))]
                b.cells.append((vtk.VTK_QUAD, q if z else q[::-1]))
                material.append(0)
    for k in range(nz):
        for i in range(nx):
            q = [b.point((i, 0, k)), b.point((i + 1, 0, k)), b.point((i + 1, 0, k + 1)),
                 b.point((i, 0, k + 1))]
            b.cells.append((vtk.VTK_QUAD, q))
            material.append(0)
    # Block B: Kuhn tets, apart from A.
    for k in range(2):
        for j in range(2):
            for i in range(2):
                for t in kuhn_tets(b, 5 + i, j, k):
                    b.cells.append((vtk.VTK_TETRA, positive(b, t)))
                    material.append(6)
    for j in range(2):
        for i in range(2):
            # Bottom faces of block B (z = 0), split along the Kuhn diagonal 000-110.
            p00, p10 = b.point((5 + i, j, 0)), b.point((6 + i, j, 0))
            p11, p01 = b.point((6 + i, j + 1, 0)), b.point((5 + i, j + 1, 0))
            b.cells.append((vtk.VTK_TRIANGLE, [p00, p11, p10]))
            b.cells.append((vtk.VTK_TRIANGLE, [p00, p01, p11]))
            material += [0, 0]
    b.cells.append((vtk.VTK_LINE, [b.point((0, 0, 0)), b.point((7, 0, 0))]))
    b.cells.append((vtk.VTK_VERTEX, [b.point((7, 2, 2))]))
    material += [0, 0]
    return b, material


def to_grid(b):
    pts = vtk.vtkPoints()
    pts.SetDataTypeToDouble()
    for p in b.pts:
        pts.InsertNextPoint(p)
    g = vtk.vtkUnstructuredGrid()
    g.SetPoints(pts)
    for c in b.cells:
        if c[0] == vtk.VTK_POLYHEDRON:
            stream = [len(c[2])]
            for f in c[2]:
                stream += [len(f)] + f
            ids = vtk.vtkIdList()
            for v in stream:
                ids.InsertNextId(v)
            g.InsertNextCell(vtk.VTK_POLYHEDRON, ids)
        else:
            g.InsertNextCell(c[0], len(c[1]), c[1])
    return g


def add_arrays(g, b, material):
    t = vtk.vtkDoubleArray()
    t.SetName("temperature")
    v = vtk.vtkFloatArray()
    v.SetName("velocity")
    v.SetNumberOfComponents(3)
    for k, n in enumerate("xyz"):
        v.SetComponentName(k, "v" + n)
    lab = vtk.vtkIntArray()
    lab.SetName("node_label")
    for i, p in enumerate(b.pts):
        t.InsertNextValue(300.0 + 10.0 * p[0] - 3.5 * p[1] * p[2] + 0.125 * i)
        v.InsertNextTuple3(p[1] - 1.5, 0.5 - p[0] / 3.0, 0.25 * p[2] * p[2])
        lab.InsertNextValue((i * 7919) % 1000 - 500)
    for a in (t, v, lab):
        g.GetPointData().AddArray(a)
    g.GetPointData().SetActiveScalars("temperature")
    m = vtk.vtkIntArray()
    m.SetName("material")
    w = vtk.vtkDoubleArray()
    w.SetName("cell_weight")
    f = vtk.vtkUnsignedCharArray()
    f.SetName("flags")
    for i, mat in enumerate(material):
        m.InsertNextValue(mat)
        w.InsertNextValue(1.0 / (i + 1))
        f.InsertNextValue((i * 37) % 256)
    for a in (m, w, f):
        g.GetCellData().AddArray(a)
    s = vtk.vtkStringArray()
    s.SetName("source")
    s.InsertNextValue("make_mixed_fixtures.py")
    s.InsertNextValue("VTK " + vtk.vtkVersion.GetVTKVersion())
    g.GetFieldData().AddArray(s)
    tv = vtk.vtkDoubleArray()
    tv.SetName("TimeValue")
    tv.InsertNextValue(0.25)
    g.GetFieldData().AddArray(tv)


def quadratic():
    b = Builder()
    ids = []
    n = 3
    for k in range(n):
        for j in range(n):
            for i in range(n):
                for t in kuhn_tets(b, i, j, k):
                    ids.append(positive(b, t))
    # Scale to [0, 1]^3 only through the coordinates written, so ids stay shared.
    mid = {}
    cells = []
    for t in ids:
        q = list(t)
        for a, c in [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]:
            key = (min(t[a], t[c]), max(t[a], t[c]))
            if key not in mid:
                pa, pc = b.pts[t[a]], b.pts[t[c]]
                mid[key] = b.point(tuple(0.5 * (pa[k] + pc[k]) for k in range(3)))
            q.append(mid[key])
        cells.append(q)
    b.pts = [tuple(x / n for x in p) for p in b.pts]
    b.cells = [(vtk.VTK_QUADRATIC_TETRA, q) for q in cells]
    g = to_grid(b)
    f = vtk.vtkDoubleArray()
    f.SetName("u")
    for p in b.pts:
        f.InsertNextValue(p[0] * p[0] + p[1] * p[2] - 0.5 * p[2])
    g.GetPointData().AddArray(f)
    c = vtk.vtkIdTypeArray()
    c.SetName("element_id")
    for i in range(len(cells)):
        c.InsertNextValue(1000 + i)
    g.GetCellData().AddArray(c)
    return g


def prisms():
    import math
    b = Builder()
    part = []
    for n, x0 in ((5, 0.0), (6, 3.0)):
        ring = [(x0 + math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n)) for i in range(n)]
        for z in (0.0, 1.0):
            ids = [b.point((x, y, z)) for x, y in ring] + [b.point((x, y, z + 1.0)) for x, y in ring]
            b.cells.append((vtk.VTK_PENTAGONAL_PRISM if n == 5 else vtk.VTK_HEXAGONAL_PRISM, ids))
            part.append(n)
    tq = vtk.vtkTriQuadraticHexahedron()
    pc = tq.GetParametricCoords()
    for x0 in (5.0, 6.0):
        ids = [b.point((x0 + pc[3 * i], pc[3 * i + 1], pc[3 * i + 2])) for i in range(27)]
        b.cells.append((vtk.VTK_TRIQUADRATIC_HEXAHEDRON, ids))
        part.append(27)
    g = to_grid(b)
    f = vtk.vtkDoubleArray()
    f.SetName("x2")
    for p in b.pts:
        f.InsertNextValue(p[0] * p[0] - p[1] + 0.5 * p[2])
    g.GetPointData().AddArray(f)
    c = vtk.vtkIntArray()
    c.SetName("part")
    for v in part:
        c.InsertNextValue(v)
    g.GetCellData().AddArray(c)
    return g


def write_xml(g, path, raw=False):
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetFileName(path)
    w.SetInputData(g)
    if raw:
        w.SetDataModeToAppended()
        w.EncodeAppendedDataOff()
        w.SetCompressorTypeToNone()
    if not w.Write():
        sys.exit("writing %s failed" % path)


def write_legacy(g, path, version, binary):
    w = vtk.vtkUnstructuredGridWriter()
    w.SetFileName(path)
    w.SetInputData(g)
    if version == 42:
        w.SetFileVersion(vtk.vtkUnstructuredGridWriter.VTK_LEGACY_READER_VERSION_4_2)
    if binary:
        w.SetFileTypeToBinary()
    if not w.Write():
        sys.exit("writing %s failed" % path)


def main():
    os.makedirs(OUT, exist_ok=True)
    b, material = mixed()
    g = to_grid(b)
    add_arrays(g, b, material)
    write_xml(g, os.path.join(OUT, "mixed.vtu"))
    write_legacy(g, os.path.join(OUT, "mixed.vtk"), 51, False)
    write_legacy(g, os.path.join(OUT, "mixed_42.vtk"), 42, True)
    write_xml(prisms(), os.path.join(OUT, "prisms.vtu"))
    q = quadratic()
    write_xml(q, os.path.join(OUT, "quadratic_tets.vtu"), raw=True)
    for name in sorted(os.listdir(OUT)):
        print(name, os.path.getsize(os.path.join(OUT, name)))


if __name__ == "__main__":
    main()
