#!/usr/bin/python3
"""Writes fixtures/structured/ with VTK 9.1's own writers: the structured data sets ParaView users
save (image data, rectilinear and curvilinear grids), each beside the unstructured grid VTK itself
makes of it (vtkAppendFilter, `*_vtk.vtu`), which the tests compare tetkit's reading against.

Every data set carries point data temperature (Float64) and velocity (Float32 x3) and cell data
material (Int32).

image.vti         5 x 4 x 3 points, spacing (0.5, 0.25, 1), origin (100000.5, -3, 7) (a far
                  offset), direction a quarter turn about z; written with 2 pieces, which VTK 9.1
                  writes (without a streaming pipeline) as two <Piece>s of the whole extent.
wavelet.vti       VTK's wavelet source (RTData, Float32) over the extent -4..4 x -3..3 x 0..2,
                  streamed by the writer as 3 pieces: three <Piece>s of different extents that
                  share their boundary points.
image_ascii.vti   the same, one piece, ascii.
image_slice.vti   a 6 x 1 x 4 x-z slice (pixels), zlib-compressed.
rect.vtr          uneven x, y, z coordinates (Float64 x, Float32 y and z), base64 binary.
curvi.vts         a quarter of a thick cylinder (r 1..2, 90 degrees, z 0..1), 4 x 6 x 3 points.
parallel/wavelet.pvti, parallel/wavelet_sg.pvts, parallel/rect.pvtr
                  parallel files from VTK's parallel writers (vtkXMLP*Writer), each naming its
                  piece files: the wavelet in 3 pieces as image data and as a structured grid
                  (vtkImageDataToPointSet), a rectilinear grid in 2 pieces (which VTK writes, from
                  an unstreamed source, as two copies of the whole extent); beside each,
                  *_vtk.vtu, what VTK's parallel reader gives, through vtkAppendFilter.
image.vtk, rect.vtk, curvi.vtk
                  the same three data sets as legacy STRUCTURED_POINTS (ASCII, version 5.1;
                  VTK's writer keeps 6 digits of the origin, about 11 of the data, and drops the
                  direction), RECTILINEAR_GRID (BINARY, 5.1) and STRUCTURED_GRID (BINARY, 4.2).
"""
import math
import os

import vtk

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fixtures", "structured")


def add_data(ds):
    temp = vtk.vtkDoubleArray()
    temp.SetName("temperature")
    vel = vtk.vtkFloatArray()
    vel.SetName("velocity")
    vel.SetNumberOfComponents(3)
    for i in range(ds.GetNumberOfPoints()):
        x, y, z = ds.GetPoint(i)
        temp.InsertNextValue(0.5 * i + (x - 100000) * 0.001 + 2 * y + 3 * z)
        vel.InsertNextTuple3(i, -i, 0.25 * i)
    ds.GetPointData().AddArray(temp)
    ds.GetPointData().SetActiveScalars("temperature")
    ds.GetPointData().AddArray(vel)
    mat = vtk.vtkIntArray()
    mat.SetName("material")
    for c in range(ds.GetNumberOfCells()):
        mat.InsertNextValue(c % 4)
    ds.GetCellData().AddArray(mat)
    return ds


def image(dims=(5, 4, 3)):
    img = vtk.vtkImageData()
    img.SetDimensions(*dims)
    img.SetSpacing(0.5, 0.25, 1.0)
    img.SetOrigin(100000.5, -3.0, 7.0)
    img.SetDirectionMatrix(0, -1, 0, 1, 0, 0, 0, 0, 1)
    return add_data(img)


def rect():
    r = vtk.vtkRectilinearGrid()
    xs, ys, zs = [0.0, 0.1, 0.35, 1.0], [-1.0, -0.5, 2.0], [3.0, 3.5, 4.25, 5.0, 7.0]
    r.SetDimensions(len(xs), len(ys), len(zs))
    for vals, arr, setter, name in (
        (xs, vtk.vtkDoubleArray(), r.SetXCoordinates, "x"),
        (ys, vtk.vtkFloatArray(), r.SetYCoordinates, "y"),
        (zs, vtk.vtkFloatArray(), r.SetZCoordinates, "z"),
    ):
        # Named, or VTK names them by their address and each run writes another file.
        arr.SetName(name)
        for v in vals:
            arr.InsertNextValue(v)
        setter(arr)
    return add_data(r)


def curvi():
    g = vtk.vtkStructuredGrid()
    ni, nj, nk = 4, 6, 3
    g.SetDimensions(ni, nj, nk)
    pts = vtk.vtkPoints()
    pts.SetDataTypeToDouble()
    for k in range(nk):
        for j in range(nj):
            for i in range(ni):
                r = 1 + i / (ni - 1)
                t = 0.5 * math.pi * j / (nj - 1)
                pts.InsertNextPoint(r * math.cos(t), r * math.sin(t), 0.5 * k)
    g.SetPoints(pts)
    return add_data(g)


def xml(writer, name, ds, mode="appended", compress=False, pieces=1):
    w = writer()
    w.SetFileName(os.path.join(OUT, name))
    w.SetInputData(ds)
    if not compress:
        w.SetCompressorTypeToNone()
    if mode == "ascii":
        w.SetDataModeToAscii()
    elif mode == "binary":
        w.SetDataModeToBinary()
    else:
        w.SetDataModeToAppended()
    w.SetNumberOfPieces(pieces)
    assert w.Write() == 1, name


def as_vtu(name, ds):
    app = vtk.vtkAppendFilter()
    app.SetInputData(ds)
    app.Update()
    xml(vtk.vtkXMLUnstructuredGridWriter, name, app.GetOutput(), mode="ascii")


def legacy(writer, name, ds, binary, version):
    w = writer()
    w.SetFileName(os.path.join(OUT, name))
    w.SetInputData(ds)
    if binary:
        w.SetFileTypeToBinary()
    w.SetFileVersion(version)
    assert w.Write() == 1, name


def main():
    os.makedirs(OUT, exist_ok=True)
    img, slc, rg, cg = image(), image((6, 1, 4)), rect(), curvi()
    xml(vtk.vtkXMLImageDataWriter, "image.vti", img, pieces=2)
    xml(vtk.vtkXMLImageDataWriter, "image_ascii.vti", img, mode="ascii")
    xml(vtk.vtkXMLImageDataWriter, "image_slice.vti", slc, mode="binary", compress=True)
    xml(vtk.vtkXMLRectilinearGridWriter, "rect.vtr", rg, mode="binary")
    xml(vtk.vtkXMLStructuredGridWriter, "curvi.vts", cg)
    for name, ds in (("image", img), ("image_slice", slc), ("rect", rg), ("curvi", cg)):
        as_vtu(name + "_vtk.vtu", ds)
    legacy(vtk.vtkStructuredPointsWriter, "image.vtk", img, False, 51)
    legacy(vtk.vtkRectilinearGridWriter, "rect.vtk", rg, True, 51)
    legacy(vtk.vtkStructuredGridWriter, "curvi.vtk", cg, True, 42)
    wave = vtk.vtkRTAnalyticSource()
    wave.SetWholeExtent(-4, 4, -3, 3, 0, 2)
    w = vtk.vtkXMLImageDataWriter()
    w.SetFileName(os.path.join(OUT, "wavelet.vti"))
    w.SetInputConnection(wave.GetOutputPort())
    w.SetCompressorTypeToNone()
    w.SetDataModeToAscii()
    w.SetNumberOfPieces(3)
    assert w.Write() == 1
    wave.UpdateWholeExtent()
    as_vtu("wavelet_vtk.vtu", wave.GetOutput())
    parallel(wave)


def parallel(wave):
    os.makedirs(os.path.join(OUT, "parallel"), exist_ok=True)
    sg = vtk.vtkImageDataToPointSet()
    sg.SetInputConnection(wave.GetOutputPort())
    rg = rect()
    cut = vtk.vtkExtractRectilinearGrid()
    cut.SetInputData(rg)
    cut.SetVOI(0, 3, 0, 2, 0, 4)
    for writer, reader, name, port, pieces in (
        (vtk.vtkXMLPImageDataWriter, vtk.vtkXMLPImageDataReader, "wavelet.pvti", wave, 3),
        (vtk.vtkXMLPStructuredGridWriter, vtk.vtkXMLPStructuredGridReader, "wavelet_sg.pvts", sg, 3),
        (vtk.vtkXMLPRectilinearGridWriter, vtk.vtkXMLPRectilinearGridReader, "rect.pvtr", cut, 2),
    ):
        path = os.path.join(OUT, "parallel", name)
        w = writer()
        w.SetFileName(path)
        w.SetInputConnection(port.GetOutputPort())
        w.SetNumberOfPieces(pieces)
        w.SetStartPiece(0)
        w.SetEndPiece(pieces - 1)
        w.SetCompressorTypeToNone()
        assert w.Write() == 1, name
        r = reader()
        r.SetFileName(path)
        r.Update()
        as_vtu(os.path.join("parallel", name.split(".")[0] + "_vtk.vtu"), r.GetOutput())


if __name__ == "__main__":
    main()
