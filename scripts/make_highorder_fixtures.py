#!/usr/bin/python3
"""Writes fixtures/highorder/ with VTK 9.1: Lagrange, Bezier and convex point set cells.

highorder.vtu (appended, zlib), highorder_51.vtk (legacy 5.1 ascii), highorder_42.vtk (legacy
4.2 binary): one grid of every Lagrange and Bezier shape vtkCellTypeSource makes in 9.1 (curve,
triangle, quadrilateral, tetrahedron, hexahedron, wedge; it has no pyramids), order 2 except the
hexahedra (order 3, 64 nodes), each shape moved along x so nothing overlaps, plus one
VTK_CONVEX_POINT_SET (a unit cube's 8 corners; vtkCellTypeSource does not make these).
Point data: vtkCellTypeSource's DistanceToCenter and Polynomial (Float32).
Cell data: HigherOrderDegrees (Int32 x3, the order per axis as VTK names it; 0 for the
convex point set) and cell_id (Int64).
Prints each file's cell type counts as VTK reads them back.
"""
import os

import vtk

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fixtures", "highorder")

SHAPES = ["CURVE", "TRIANGLE", "QUADRILATERAL", "TETRAHEDRON", "HEXAHEDRON", "WEDGE"]
DIM = {"CURVE": 1, "TRIANGLE": 2, "QUADRILATERAL": 2}


def source(kind, shape):
    s = vtk.vtkCellTypeSource()
    s.SetCellType(getattr(vtk, "VTK_%s_%s" % (kind, shape)))
    s.SetBlocksDimensions(1, 1, 1)
    order = 3 if shape == "HEXAHEDRON" else 2
    s.SetCellOrder(order)
    s.Update()
    return s.GetOutput(), order


def main():
    os.makedirs(OUT, exist_ok=True)
    append = vtk.vtkAppendFilter()
    degrees = []
    shift = 0.0
    for kind in ["LAGRANGE", "BEZIER"]:
        for shape in SHAPES:
            g, order = source(kind, shape)
            t = vtk.vtkTransform()
            t.Translate(shift, 0, 0)
            f = vtk.vtkTransformFilter()
            f.SetTransform(t)
            f.SetInputData(g)
            f.Update()
            append.AddInputData(f.GetOutput())
            d = DIM.get(shape, 3)
            degrees += [tuple(order if k < d else 0 for k in range(3))] * g.GetNumberOfCells()
            shift += 2.0
    cube = vtk.vtkUnstructuredGrid()
    pts = vtk.vtkPoints()
    for k in range(8):
        pts.InsertNextPoint(shift + (k & 1), (k >> 1) & 1, (k >> 2) & 1)
    cube.SetPoints(pts)
    cube.InsertNextCell(vtk.VTK_CONVEX_POINT_SET, 8, list(range(8)))
    for name in ["DistanceToCenter", "Polynomial"]:
        a = vtk.vtkFloatArray()
        a.SetName(name)
        for k in range(8):
            a.InsertNextValue(float(k))
        cube.GetPointData().AddArray(a)
    append.AddInputData(cube)
    degrees.append((0, 0, 0))
    append.Update()
    g = append.GetOutput()
    hod = vtk.vtkIntArray()
    hod.SetName("HigherOrderDegrees")
    hod.SetNumberOfComponents(3)
    ids = vtk.vtkTypeInt64Array()
    ids.SetName("cell_id")
    for i, d in enumerate(degrees):
        hod.InsertNextTuple3(*d)
        ids.InsertNextValue(i)
    assert len(degrees) == g.GetNumberOfCells()
    g.GetCellData().AddArray(hod)
    g.GetCellData().AddArray(ids)

    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetFileName(os.path.join(OUT, "highorder.vtu"))
    w.SetInputData(g)
    w.Write()
    w = vtk.vtkUnstructuredGridWriter()
    w.SetFileName(os.path.join(OUT, "highorder_51.vtk"))
    w.SetInputData(g)
    w.Write()
    w = vtk.vtkUnstructuredGridWriter()
    w.SetFileName(os.path.join(OUT, "highorder_42.vtk"))
    w.SetFileVersion(42)
    w.SetFileTypeToBinary()
    w.SetInputData(g)
    w.Write()

    for name in ["highorder.vtu", "highorder_51.vtk", "highorder_42.vtk"]:
        path = os.path.join(OUT, name)
        if name.endswith(".vtu"):
            r = vtk.vtkXMLUnstructuredGridReader()
        else:
            r = vtk.vtkUnstructuredGridReader()
        r.SetFileName(path)
        r.Update()
        out = r.GetOutput()
        counts = {}
        for i in range(out.GetNumberOfCells()):
            key = (out.GetCellType(i), out.GetCell(i).GetNumberOfPoints())
            counts[key] = counts.get(key, 0) + 1
        print(name, out.GetNumberOfPoints(), "points", sorted(counts.items()))


if __name__ == "__main__":
    main()
