#!/usr/bin/python3
"""Writes fixtures/scenes/ (surfaces in fixtures/scenes/surfaces/) with VTK 9.1: closed body surfaces in every format a scene reads, two
broken ones for the error tests, and a small tet mesh (a Delaunay-tetrahedralized cube) to
classify.

sphere.stl       binary STL, vtkSphereSource (r 0.3 at (0.5, 0.5, 0.5), 16 x 12), welded by reading
cube_ascii.stl   ascii STL of a triangulated unit cube spanning [0.25, 0.75]^3
cylinder.obj     OBJ of a capped vtkCylinderSource (axis y, r 0.2, height 0.8) at the cube centre
cone.vtk         legacy VTK POLYDATA (ascii) of a capped vtkConeSource (its base is one polygon)
sphere.vtp       VTK XML PolyData, VTK's default (appended raw, zlib-compressed)
sphere_ascii.vtp VTK XML PolyData in ascii
open.stl         the cube with one face missing (must be refused: open surface)
flipped.obj      the cube with one triangle reversed (must be refused: inconsistent orientation)
cube_mesh.vtk    tets (legacy VTK) of a 5 x 5 x 5 lattice in [0, 1]^3 (vtkDelaunay3D), point data `scalar`
                 (x + y + z) and cell data `cell_id`
"""
import os

import vtk

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fixtures", "scenes")
os.makedirs(os.path.join(OUT, "surfaces"), exist_ok=True)


def tri(src):
    t = vtk.vtkTriangleFilter()
    t.SetInputConnection(src.GetOutputPort())
    t.Update()
    return t.GetOutput()


def out(name):
    """Surfaces go to surfaces/ (polydata: not meshes the unstructured readers must accept)."""
    return os.path.join(OUT, name if name.endswith(".vtk") and "mesh" in name else os.path.join("surfaces", name))


sphere = vtk.vtkSphereSource()
sphere.SetCenter(0.5, 0.5, 0.5)
sphere.SetRadius(0.3)
sphere.SetThetaResolution(16)
sphere.SetPhiResolution(12)
sphere.Update()

w = vtk.vtkSTLWriter()
w.SetInputConnection(sphere.GetOutputPort())
w.SetFileTypeToBinary()
w.SetFileName(out("sphere.stl"))
w.Write()

w = vtk.vtkXMLPolyDataWriter()
w.SetInputConnection(sphere.GetOutputPort())
w.SetFileName(out("sphere.vtp"))
w.Write()

w = vtk.vtkXMLPolyDataWriter()
w.SetInputConnection(sphere.GetOutputPort())
w.SetDataModeToAscii()
w.SetFileName(out("sphere_ascii.vtp"))
w.Write()

cube = vtk.vtkCubeSource()
cube.SetBounds(0.25, 0.75, 0.25, 0.75, 0.25, 0.75)
cube_t = tri(cube)
w = vtk.vtkSTLWriter()
w.SetInputData(cube_t)
w.SetFileTypeToASCII()
w.SetFileName(out("cube_ascii.stl"))
w.Write()

cyl = vtk.vtkCylinderSource()
cyl.SetCenter(0.5, 0.5, 0.5)
cyl.SetRadius(0.2)
cyl.SetHeight(0.8)
cyl.SetResolution(12)
cyl.CappingOn()
w = vtk.vtkOBJWriter()
w.SetInputData(tri(cyl))
w.SetFileName(out("cylinder.obj"))
w.Write()

cone = vtk.vtkConeSource()
cone.SetCenter(0.5, 0.5, 0.5)
cone.SetRadius(0.3)
cone.SetHeight(0.6)
cone.SetResolution(10)
cone.CappingOn()
cone.Update()
w = vtk.vtkPolyDataWriter()
w.SetInputConnection(cone.GetOutputPort())
w.SetFileName(out("cone.vtk"))
w.Write()

# Broken surfaces: the cube's triangles, one removed / one reversed.
cd = cube_t
pts = [cd.GetPoint(i) for i in range(cd.GetNumberOfPoints())]
tris = []
for c in range(cd.GetNumberOfCells()):
    ids = cd.GetCell(c).GetPointIds()
    tris.append([ids.GetId(k) for k in range(3)])
with open(out("open.stl"), "w") as f:
    f.write("solid open\n")
    for t in tris[:-1]:
        f.write(" facet normal 0 0 0\n  outer loop\n")
        for i in t:
            f.write("   vertex %r %r %r\n" % pts[i])
        f.write("  endloop\n endfacet\n")
    f.write("endsolid open\n")
with open(out("flipped.obj"), "w") as f:
    for p in pts:
        f.write("v %r %r %r\n" % p)
    for k, t in enumerate(tris):
        if k == 0:
            t = t[::-1]
        f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))

# A small tet mesh: Delaunay tets of a lattice (degenerate cospherical ties are VTK's business;
# every tet it keeps is valid).
points = vtk.vtkPoints()
n = 4
for k in range(n + 1):
    for j in range(n + 1):
        for i in range(n + 1):
            points.InsertNextPoint(i / n, j / n, k / n)
poly = vtk.vtkPolyData()
poly.SetPoints(points)
d = vtk.vtkDelaunay3D()
d.SetInputData(poly)
d.Update()
grid = d.GetOutput()
scalar = vtk.vtkDoubleArray()
scalar.SetName("scalar")
for i in range(grid.GetNumberOfPoints()):
    p = grid.GetPoint(i)
    scalar.InsertNextValue(p[0] + p[1] + p[2])
grid.GetPointData().AddArray(scalar)
cid = vtk.vtkIntArray()
cid.SetName("cell_id")
for i in range(grid.GetNumberOfCells()):
    cid.InsertNextValue(i)
grid.GetCellData().AddArray(cid)
w = vtk.vtkUnstructuredGridWriter()
w.SetInputData(grid)
w.SetFileName(out("cube_mesh.vtk"))
w.Write()
