#!/usr/bin/python3
"""Writes fixtures/collections/ with VTK 9.1's own writers: the collections ParaView users and FEM
codes save, made of a small tetrahedralized box (3 x 3 x 3 cubes, 5 tets each: 135 tets).

Every mesh carries point data temperature (Float64) and velocity (Float32 x3) and cell data
material (Int32) and pressure (Float64); the blocks' x offset tells them apart.

multiblock.vtm (vtkXMLMultiBlockDataWriter): block 0 "solid"; block 1 "shell", a nested
  multiblock of "inner" and "outer"; block 2 "empty" (no data set). 3 meshes, in that order.
differing.vtm: block "a" has all four arrays plus a_only (cell, Float32); block "b" lacks velocity
  and has b_only (point, Int32): merged, temperature, material and pressure remain.
kinds.vtm: an unstructured grid "volume", its surface as polydata "surface" (.vtp), and image
  data "image" (.vti), which tetkit reads as voxels.
parallel.pvtu (vtkXMLPUnstructuredGridWriter, 3 pieces via vtkExtractUnstructuredGridPiece).
extra_arrays.pvtu: written as parallel.pvtu, then piece 1 rewritten with an extra cell array
  rank_debug that the .pvtu does not declare (FEM codes write such pieces).
refs.vtm: written as ParaView lays a multiblock out, naming parallel.pvtu, a legacy .vtk block and
  multiblock.vtm (nested collections).
series.pvd: three time steps (0, 0.5, 1) of two parts each, per-step .vtu files from
  vtkXMLUnstructuredGridWriter and the .pvd XML as ParaView's PVD writer writes it; temperature
  grows with time. Its entries are listed out of time order, as some codes append them.
"""
import os
import shutil

import vtk

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fixtures", "collections")


def box(shift, time=0.0):
    img = vtk.vtkImageData()
    img.SetDimensions(4, 4, 4)
    img.SetSpacing(1.0 / 3, 1.0 / 3, 1.0 / 3)
    img.SetOrigin(shift, 0, 0)
    tri = vtk.vtkDataSetTriangleFilter()
    tri.SetInputData(img)
    tri.Update()
    ug = vtk.vtkUnstructuredGrid()
    ug.DeepCopy(tri.GetOutput())
    temp = vtk.vtkDoubleArray()
    temp.SetName("temperature")
    vel = vtk.vtkFloatArray()
    vel.SetName("velocity")
    vel.SetNumberOfComponents(3)
    for i in range(ug.GetNumberOfPoints()):
        x, y, z = ug.GetPoint(i)
        temp.InsertNextValue(x + 2 * y + 3 * z + 10 * time)
        vel.InsertNextTuple3(y, -x, z * shift)
    ug.GetPointData().AddArray(temp)
    ug.GetPointData().SetActiveScalars("temperature")
    ug.GetPointData().AddArray(vel)
    mat = vtk.vtkIntArray()
    mat.SetName("material")
    pres = vtk.vtkDoubleArray()
    pres.SetName("pressure")
    for c in range(ug.GetNumberOfCells()):
        mat.InsertNextValue(int(shift) * 10 + c % 3)
        pres.InsertNextValue(0.5 * c + shift)
    ug.GetCellData().AddArray(mat)
    ug.GetCellData().AddArray(pres)
    return ug


def named(mb, i, block, name):
    mb.SetBlock(i, block)
    mb.GetMetaData(i).Set(vtk.vtkCompositeDataSet.NAME(), name)


def write_vtm(name, mb):
    w = vtk.vtkXMLMultiBlockDataWriter()
    w.SetFileName(os.path.join(OUT, name))
    w.SetInputData(mb)
    assert w.Write() == 1, name


def write_vtu(path, ug):
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetFileName(path)
    w.SetInputData(ug)
    assert w.Write() == 1, path


def write_pvtu(name, ug, pieces=3):
    ex = vtk.vtkExtractUnstructuredGridPiece()
    ex.SetInputData(ug)
    w = vtk.vtkXMLPUnstructuredGridWriter()
    w.SetFileName(os.path.join(OUT, name))
    w.SetInputConnection(ex.GetOutputPort())
    w.SetNumberOfPieces(pieces)
    w.SetStartPiece(0)
    w.SetEndPiece(pieces - 1)
    assert w.Write() == 1, name


def main():
    shutil.rmtree(OUT, ignore_errors=True)
    os.makedirs(OUT)

    mb = vtk.vtkMultiBlockDataSet()
    named(mb, 0, box(0), "solid")
    shell = vtk.vtkMultiBlockDataSet()
    named(shell, 0, box(2), "inner")
    named(shell, 1, box(4), "outer")
    named(mb, 1, shell, "shell")
    named(mb, 2, None, "empty")
    write_vtm("multiblock.vtm", mb)

    a, b = box(0), box(2)
    extra = vtk.vtkFloatArray()
    extra.SetName("a_only")
    for c in range(a.GetNumberOfCells()):
        extra.InsertNextValue(c)
    a.GetCellData().AddArray(extra)
    b.GetPointData().RemoveArray("velocity")
    only = vtk.vtkIntArray()
    only.SetName("b_only")
    for i in range(b.GetNumberOfPoints()):
        only.InsertNextValue(i)
    b.GetPointData().AddArray(only)
    mb = vtk.vtkMultiBlockDataSet()
    named(mb, 0, a, "a")
    named(mb, 1, b, "b")
    write_vtm("differing.vtm", mb)

    vol = box(0)
    surf = vtk.vtkDataSetSurfaceFilter()
    surf.SetInputData(vol)
    surf.Update()
    img = vtk.vtkImageData()
    img.SetDimensions(2, 2, 2)
    mb = vtk.vtkMultiBlockDataSet()
    named(mb, 0, vol, "volume")
    named(mb, 1, surf.GetOutput(), "surface")
    named(mb, 2, img, "image")
    write_vtm("kinds.vtm", mb)

    write_pvtu("parallel.pvtu", box(0))
    write_pvtu("extra_arrays.pvtu", box(6))
    r = vtk.vtkXMLUnstructuredGridReader()
    piece1 = os.path.join(OUT, "extra_arrays_1.vtu")
    r.SetFileName(piece1)
    r.Update()
    p1 = r.GetOutput()
    rank = vtk.vtkIntArray()
    rank.SetName("rank_debug")
    for c in range(p1.GetNumberOfCells()):
        rank.InsertNextValue(1)
    p1.GetCellData().AddArray(rank)
    write_vtu(piece1, p1)

    legacy = vtk.vtkUnstructuredGridWriter()
    legacy.SetFileName(os.path.join(OUT, "refs", "legacy_block.vtk"))
    os.makedirs(os.path.join(OUT, "refs"))
    legacy.SetInputData(box(8))
    legacy.SetFileTypeToBinary()
    assert legacy.Write() == 1
    with open(os.path.join(OUT, "refs.vtm"), "w") as f:
        f.write(
            '<?xml version="1.0"?>\n'
            '<VTKFile type="vtkMultiBlockDataSet" version="1.0" byte_order="LittleEndian" '
            'header_type="UInt32">\n'
            "  <vtkMultiBlockDataSet>\n"
            '    <DataSet index="0" name="parallel" file="parallel.pvtu"/>\n'
            '    <Block index="1" name="more">\n'
            '      <DataSet index="0" name="legacy" file="refs/legacy_block.vtk"/>\n'
            '      <DataSet index="1" name="nested" file="multiblock.vtm"/>\n'
            "    </Block>\n"
            "  </vtkMultiBlockDataSet>\n"
            "</VTKFile>\n"
        )

    os.makedirs(os.path.join(OUT, "series"))
    entries = []
    for step, t in enumerate([0.0, 0.5, 1.0]):
        for part in range(2):
            rel = f"series/series_{step}_{part}.vtu"
            write_vtu(os.path.join(OUT, rel), box(2 * part, t))
            entries.append(
                f'    <DataSet timestep="{t:g}" group="" part="{part}" file="{rel}"/>\n'
            )
    # The last step's entries first: readers sort by time, not by position.
    entries = entries[4:] + entries[:4]
    with open(os.path.join(OUT, "series.pvd"), "w") as f:
        f.write(
            '<?xml version="1.0"?>\n'
            '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian" '
            'header_type="UInt32" compressor="vtkZLibDataCompressor">\n'
            "  <Collection>\n" + "".join(entries) + "  </Collection>\n</VTKFile>\n"
        )


if __name__ == "__main__":
    main()
