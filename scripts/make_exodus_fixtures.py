#!/usr/bin/python3
"""Writes the Exodus II fixtures in fixtures/exodus/ with VTK's vtkExodusIIWriter (NetCDF CDF-2),
and hand.exo (CDF-1) byte by byte with the cells VTK's writer cannot write; beside each X.exo what
VTK's vtkExodusIIReader makes of it, its blocks appended into one grid, as X_vtk.vtu.

Run with VTK's Python: /usr/bin/python3 scripts/make_exodus_fixtures.py
Then scripts/make_exodus_nc4_fixtures.sh makes their NetCDF-4 (HDF5) copies in fixtures/exodus/nc4/
(with nccopy from netcdf-bin, needed only to regenerate them).
"""
import os
import sys

from netcdf_classic import Cdf, text
import vtk
from vtk.util import numpy_support as ns
from vtk.util.vtkAlgorithm import VTKPythonAlgorithmBase
import numpy as np

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fixtures", "exodus")


def arr(name, values, cls=vtk.vtkDoubleArray, comps=1):
    a = cls()
    a.SetName(name)
    a.SetNumberOfComponents(comps)
    for v in np.asarray(values).reshape(-1):
        a.InsertNextValue(v)
    return a


def tets():
    """A 3x2x2 box of voxels cut into tetrahedra, in two blocks (ids 10 and 20) by x."""
    img = vtk.vtkImageData()
    img.SetDimensions(4, 3, 3)
    img.SetSpacing(0.5, 0.5, 0.5)
    tri = vtk.vtkDataSetTriangleFilter()
    tri.SetInputData(img)
    tri.Update()
    g = vtk.vtkUnstructuredGrid()
    g.DeepCopy(tri.GetOutput())
    n, m = g.GetNumberOfPoints(), g.GetNumberOfCells()
    pts = ns.vtk_to_numpy(g.GetPoints().GetData())
    centres = []
    for c in range(m):
        ids = g.GetCell(c).GetPointIds()
        centres.append(np.mean([pts[ids.GetId(k)] for k in range(4)], axis=0))
    centres = np.array(centres)
    g.GetCellData().AddArray(arr("ObjectId", np.where(centres[:, 0] < 0.75, 10, 20), vtk.vtkIntArray))
    g.GetCellData().AddArray(arr("pressure", centres[:, 0] * 2 + centres[:, 2]))
    g.GetPointData().AddArray(arr("temperature", pts[:, 0] + 10 * pts[:, 1] + 100 * pts[:, 2]))
    g.GetPointData().AddArray(arr("GlobalNodeId", np.arange(n) * 3 + 7, vtk.vtkIdTypeArray))
    g.GetCellData().AddArray(arr("GlobalElementId", np.arange(m) * 2 + 100, vtk.vtkIdTypeArray))
    return g


def mixed():
    """A hexahedron with a wedge on top and a pyramid beside it."""
    p = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1),
         (0, 0.5, 1.5), (1, 0.5, 1.5), (1.5, 0.5, 0.5)]
    g = vtk.vtkUnstructuredGrid()
    pts = vtk.vtkPoints()
    pts.SetDataTypeToFloat()
    for q in p:
        pts.InsertNextPoint(q)
    g.SetPoints(pts)
    g.InsertNextCell(vtk.VTK_HEXAHEDRON, 8, [0, 1, 2, 3, 4, 5, 6, 7])
    # As vtkWedge's documentation has it: the first triangle's normal points away from the
    # second (VTK's writer and reader pass wedge nodes through unchanged).
    g.InsertNextCell(vtk.VTK_WEDGE, 6, [4, 8, 7, 5, 9, 6])
    # The base's normal points towards the apex.
    g.InsertNextCell(vtk.VTK_PYRAMID, 5, [1, 2, 6, 5, 10])
    g.GetCellData().AddArray(arr("ObjectId", [1, 2, 3], vtk.vtkIntArray))
    g.GetCellData().AddArray(arr("quality", [0.5, 0.25, 0.125]))
    g.GetPointData().AddArray(arr("height", [q[2] for q in p]))
    return g


def quadratic():
    """Second-order cells, one per block, their mid-edge nodes bent."""
    g = vtk.vtkUnstructuredGrid()
    pts = vtk.vtkPoints()
    pts.SetDataTypeToDouble()
    g.SetPoints(pts)

    def add(cell, offset):
        c = cell()
        k = c.GetNumberOfPoints()
        pc = c.GetParametricCoords()
        ids = []
        for i in range(k):
            r, s, t = pc[3 * i:3 * i + 3]
            # Bend the mid-edge nodes a little so that a wrong order shows.
            bend = 0.05 * r * s if i >= 4 else 0.0
            ids.append(pts.InsertNextPoint(r + offset + bend, s, t + bend))
        g.InsertNextCell(c.GetCellType(), k, ids)

    add(vtk.vtkQuadraticTetra, 0.0)
    add(vtk.vtkQuadraticHexahedron, 2.0)
    add(vtk.vtkQuadraticWedge, 4.0)
    add(vtk.vtkQuadraticPyramid, 6.0)
    add(vtk.vtkQuadraticTriangle, 8.0)
    add(vtk.vtkQuadraticQuad, 10.0)
    # VTK 9.1's writer cannot write a 27-node hexahedron (it names it 'unknown cell type') nor a
    # 9-node quadrilateral (its reader gives 8 nodes back), so those are not here.
    g.GetCellData().AddArray(arr("ObjectId", [1, 2, 3, 4, 5, 6], vtk.vtkIntArray))
    n = g.GetNumberOfPoints()
    g.GetPointData().AddArray(arr("x", [pts.GetPoint(i)[0] for i in range(n)]))
    return g


class TimeSource(VTKPythonAlgorithmBase):
    """The tet box with a displacement-like field over three time steps."""

    TIMES = [0.0, 0.5, 1.25]

    def __init__(self):
        VTKPythonAlgorithmBase.__init__(self, nInputPorts=0, nOutputPorts=1,
                                        outputType="vtkUnstructuredGrid")

    def RequestInformation(self, request, inInfo, outInfo):
        info = outInfo.GetInformationObject(0)
        sdde = vtk.vtkStreamingDemandDrivenPipeline
        info.Set(sdde.TIME_STEPS(), self.TIMES, len(self.TIMES))
        info.Set(sdde.TIME_RANGE(), [self.TIMES[0], self.TIMES[-1]], 2)
        return 1

    def RequestData(self, request, inInfo, outInfo):
        info = outInfo.GetInformationObject(0)
        t = info.Get(vtk.vtkStreamingDemandDrivenPipeline.UPDATE_TIME_STEP()) \
            if info.Has(vtk.vtkStreamingDemandDrivenPipeline.UPDATE_TIME_STEP()) else 0.0
        g = tets()
        pts = ns.vtk_to_numpy(g.GetPoints().GetData())
        g.GetPointData().AddArray(arr("phi", np.sin(pts[:, 0] * 3 + t)))
        g.GetCellData().AddArray(arr("energy", np.full(g.GetNumberOfCells(), t * t)))
        out = vtk.vtkUnstructuredGrid.GetData(outInfo)
        out.ShallowCopy(g)
        return 1


def hand_written(name, cdf):
    """A 27-node hexahedron and a 9-node quadrilateral (which VTK 9.1's writer cannot write),
    nodes placed in Exodus's order (corners, bottom edges, vertical edges, top edges, centre,
    faces -z, +z, -x, +x, -y, +y), two time steps, a nodal, an element and a global variable and
    a node set, written by hand as CDF-1 (`cdf` 1) or CDF-5 (5)."""
    c = [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1), (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]
    mid = lambda *k: tuple(np.mean([c[i] for i in k], axis=0))
    hex27 = c + [mid(0, 1), mid(1, 2), mid(2, 3), mid(3, 0),
                 mid(0, 4), mid(1, 5), mid(2, 6), mid(3, 7),
                 mid(4, 5), mid(5, 6), mid(6, 7), mid(7, 4),
                 (0, 0, 0), (0, 0, -1), (0, 0, 1), (-1, 0, 0), (1, 0, 0), (0, -1, 0), (0, 1, 0)]
    # Bend the mid nodes a little so that a wrong order shows.
    hex27 = [p if i < 8 else (p[0] + 0.03 * (i - 8) / 19, p[1], p[2]) for i, p in enumerate(hex27)]
    quad9 = [(3, -1, 0), (5, -1, 0), (5, 1, 0), (3, 1, 0), (4, -1, 0), (5, 0, 0), (4, 1, 0), (3, 0, 0), (4.1, 0.05, 0)]
    pts = hex27 + quad9
    n = len(pts)
    f = Cdf(cdf)
    f.numrecs = 2
    # The attributes the Exodus library wants before it opens a file.
    f.global_attrs = [("api_version", "f", [8.03]), ("version", "f", [8.03]),
                      ("floating_point_word_size", "i", [8]), ("file_size", "i", [1]),
                      ("maximum_name_length", "i", [32]), ("int64_status", "i", [0]),
                      ("title", "c", list(b"hand-written"))]
    t = ("time_step", 0)
    f.dim("len_name", 33)
    f.dim("num_dim", 3)
    f.dim("num_nodes", n)
    f.dim("num_elem", 2)
    f.dim("num_el_blk", 2)
    f.var("time_whole", [t], "d", [0.0, 0.75])
    for k, axis in enumerate("xyz"):
        f.var("coord" + axis, [("num_nodes", n)], "d", [p[k] for p in pts])
    f.var("eb_prop1", [("num_el_blk", 2)], "i", [5, 6], [("name", "c", list(b"ID"))])
    f.var("eb_names", [("num_el_blk", 2), ("len_name", 33)], "c", text(["brick", "plate"]))
    f.var("connect1", [("num_el_in_blk1", 1), ("num_nod_per_el1", 27)], "i", list(range(1, 28)),
          [("elem_type", "c", list(b"HEX27"))])
    f.var("connect2", [("num_el_in_blk2", 1), ("num_nod_per_el2", 9)], "i", list(range(28, 37)),
          [("elem_type", "c", list(b"SHELL9"))])
    f.dim("num_nod_var", 1)
    f.var("name_nod_var", [("num_nod_var", 1), ("len_name", 33)], "c", text(["dist"]))
    f.var("vals_nod_var1", [t, ("num_nodes", n)], "d",
          [float(np.linalg.norm(p)) * s for s in (1, 2) for p in pts])
    f.dim("num_elem_var", 1)
    f.var("name_elem_var", [("num_elem_var", 1), ("len_name", 33)], "c", text(["heat"]))
    # Both blocks hold the variable: NaN for a block left out (the reader's unit tests cover it)
    # is what VTK 9.1 cannot read back from the ASCII legacy files tests/interop.rs writes.
    f.var("elem_var_tab", [("num_el_blk", 2), ("num_elem_var", 1)], "i", [1, 1])
    f.var("vals_elem_var1eb1", [t, ("num_el_in_blk1", 1)], "d", [1.0, 2.0])
    f.var("vals_elem_var1eb2", [t, ("num_el_in_blk2", 1)], "d", [3.0, 4.0])
    f.dim("num_glo_var", 1)
    f.var("name_glo_var", [("num_glo_var", 1), ("len_name", 33)], "c", text(["work"]))
    f.var("vals_glo_var", [t, ("num_glo_var", 1)], "d", [1.0, 2.0])
    f.dim("num_node_sets", 1)
    f.var("ns_prop1", [("num_node_sets", 1)], "i", [1])
    f.var("ns_names", [("num_node_sets", 1), ("len_name", 33)], "c", text(["bottom"]))
    f.var("node_ns1", [("num_nod_ns1", 4)], "i", [1, 2, 3, 4])
    path = os.path.join(OUT, name + ".exo")
    with open(path, "wb") as out:
        out.write(f.bytes())
    reference(path, os.path.join(OUT, name + "_vtk.vtu"))


def write(name, source, all_steps=False):
    path = os.path.join(OUT, name + ".exo")
    w = vtk.vtkExodusIIWriter()
    w.SetFileName(path)
    if isinstance(source, vtk.vtkAlgorithm):
        w.SetInputConnection(source.GetOutputPort())
    else:
        w.SetInputData(source)
    w.SetWriteAllTimeSteps(all_steps)
    w.SetStoreDoubles(True)
    w.Write()
    reference(path, os.path.join(OUT, name + "_vtk.vtu"))


def reference(path, out):
    r = vtk.vtkExodusIIReader()
    r.SetFileName(path)
    r.UpdateInformation()
    for ot in (r.ELEM_BLOCK, r.NODAL, r.ELEM_BLOCK_ELEM_CONN, r.GLOBAL, r.NODE_SET, r.SIDE_SET):
        r.SetAllArrayStatus(ot, 1)
    r.SetGenerateObjectIdCellArray(1)
    r.SetGenerateGlobalElementIdArray(1)
    r.SetGenerateGlobalNodeIdArray(1)
    r.Update()
    # The blocks appended in the reader's order (vtkMergeBlocks is not in VTK 9.1): each block
    # brings the points its cells use, so points shared by blocks appear once per block.
    m = vtk.vtkAppendFilter()
    it = r.GetOutput().NewIterator()
    it.InitTraversal()
    while not it.IsDoneWithTraversal():
        m.AddInputData(it.GetCurrentDataObject())
        it.GoToNextItem()
    m.Update()
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetFileName(out)
    w.SetInputData(m.GetOutput())
    w.SetDataModeToAscii()
    w.Write()


def main():
    os.makedirs(OUT, exist_ok=True)
    write("tets", tets())
    write("mixed", mixed())
    write("quadratic", quadratic())
    write("steps", TimeSource(), all_steps=True)
    hand_written("hand", 1)
    hand_written("hand5", 5)


if __name__ == "__main__":
    sys.exit(main())
