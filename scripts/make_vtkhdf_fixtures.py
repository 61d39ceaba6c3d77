#!/usr/bin/python3
"""Writes the VTKHDF (UnstructuredGrid) fixtures in fixtures/vtkhdf/ with h5py, following the
VTKHDF specification (https://docs.vtk.org/en/latest/vtk_file_formats/vtkhdf_file_format/), and
beside each good X.vtkhdf what VTK 9.1's vtkHDFReader makes of it, as X_vtk.vtu (binary, written
by vtkXMLUnstructuredGridWriter), so that tests compare tetkit's reading with VTK's without VTK.

fixtures/vtkhdf/ was made with this script: Debian's python3-h5py 3.7.0 (HDF5 1.10), VTK 9.1.0.
Run: /usr/bin/python3 scripts/make_vtkhdf_fixtures.py

Good files (all read by VTK 9.1's vtkHDFReader; see check_vtk below):
  tets.vtkhdf        tets of a 4x3x3 lattice, float64 points, point 'temperature' (float32),
                     point 'velocity' (float64 x3), cell 'material' (int32), cell 'tensor'
                     (float32 x9), field 'time' (float64, 2 values), field 'ids' (int64 2 x3)
  two_pieces.vtkhdf  two pieces, each with its own points and piece-relative connectivity
  float32.hdf        float32 points, uint16 point array, int8 cell array
  mixed.vtkhdf       a hexahedron, two wedges, a pyramid and a tet; uint64 cell data
  gzip.vtkhdf        tets.vtkhdf's content in deflate-compressed chunked datasets
  version2.vtkhdf    Version [2, 0], no Steps (VTK 9.1 warns it supports 1.0, and reads it)
  userblock.vtkhdf   the HDF5 file behind a 512-byte user block
Bad files (tetkit refuses each, naming the problem):
  bad_type.vtkhdf          Type "ImageData"
  bad_connectivity.vtkhdf  a connectivity id past the piece's points
  bad_offsets.vtkhdf       offsets decreasing
  bad_cellsize.vtkhdf      a tetra with 5 points
  bad_points.vtkhdf        Points N x 2
  bad_pointdata.vtkhdf     a point array one tuple short
  polyhedron.vtkhdf        a VTK_POLYHEDRON cell (type 42), not read
  temporal.vtkhdf          a Steps group (version 2 temporal data), not read
  truncated.vtkhdf         tets.vtkhdf cut to its first 3000 bytes
string_field.vtkhdf (fixed- and variable-length string datasets in FieldData, a variable-length
Type, an int32 Version, PointData's attribute Scalars) tetkit reads, the strings kept; it is left
out of the VTK comparison.
"""
import os

import h5py
import numpy as np
import vtk
from vtk.util import numpy_support as ns

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fixtures", "vtkhdf")


def tet_lattice(dims=(4, 3, 3), origin=(0.0, 0.0, 0.0)):
    img = vtk.vtkImageData()
    img.SetDimensions(*dims)
    img.SetSpacing(0.5, 0.5, 0.5)
    img.SetOrigin(*origin)
    tri = vtk.vtkDataSetTriangleFilter()
    tri.SetInputData(img)
    tri.Update()
    g = tri.GetOutput()
    pts = ns.vtk_to_numpy(g.GetPoints().GetData()).astype(np.float64)
    types = ns.vtk_to_numpy(g.GetCellTypesArray()).astype(np.uint8)
    offsets = ns.vtk_to_numpy(g.GetCells().GetOffsetsArray()).astype(np.int64)
    conn = ns.vtk_to_numpy(g.GetCells().GetConnectivityArray()).astype(np.int64)
    return pts, types, offsets, conn


def piece_arrays(pts, ncells, shift=0.0):
    n = len(pts)
    temperature = (pts[:, 0] * 10.0 + pts[:, 1] + shift).astype(np.float32)
    velocity = np.stack([pts[:, 1], -pts[:, 0], pts[:, 2] * 0.5 + shift], axis=1).astype(np.float64)
    material = (np.arange(ncells) % 3 + 1).astype(np.int32)
    tensor = (np.arange(ncells * 9) * 0.25 + shift).reshape(ncells, 9).astype(np.float32)
    return {"temperature": temperature, "velocity": velocity}, {"material": material, "tensor": tensor}, n


def write(path, pieces, field=None, dtype_type="UnstructuredGrid", version=(1, 0), gzip=False,
          userblock=0):
    """pieces: list of (points, types, offsets, connectivity, point_data, cell_data)."""
    with h5py.File(path, "w", userblock_size=userblock) as f:
        root = f.create_group("VTKHDF")
        root.attrs["Version"] = np.array(version, dtype=np.int64)
        # Fixed-length ASCII, as VTK writes it (VTK 9.1's reader reads no variable-length string).
        root.attrs.create("Type", np.bytes_(dtype_type), dtype=h5py.string_dtype("ascii", len(dtype_type)))

        def ds(group, name, data):
            data = np.asarray(data)
            if gzip and data.size > 0:
                group.create_dataset(name, data=data, compression="gzip", compression_opts=6,
                                     chunks=tuple(max(1, min(s, 64)) for s in data.shape))
            else:
                group.create_dataset(name, data=data)

        ds(root, "NumberOfPoints", np.array([len(p[0]) for p in pieces], dtype=np.int64))
        ds(root, "NumberOfCells", np.array([len(p[1]) for p in pieces], dtype=np.int64))
        ds(root, "NumberOfConnectivityIds", np.array([len(p[3]) for p in pieces], dtype=np.int64))
        ds(root, "Points", np.concatenate([p[0] for p in pieces]))
        ds(root, "Types", np.concatenate([p[1] for p in pieces]))
        ds(root, "Offsets", np.concatenate([p[2] for p in pieces]))
        ds(root, "Connectivity", np.concatenate([p[3] for p in pieces]))
        for gname, idx in (("PointData", 4), ("CellData", 5)):
            g = root.create_group(gname)
            for name in pieces[0][idx]:
                ds(g, name, np.concatenate([p[idx][name] for p in pieces]))
        fd = root.create_group("FieldData")
        for name, v in (field or {}).items():
            ds(fd, name, v)


def tets_piece(shift=0.0, origin=(0.0, 0.0, 0.0), dims=(4, 3, 3)):
    pts, types, offsets, conn = tet_lattice(dims, origin)
    pd, cd, _ = piece_arrays(pts, len(types), shift)
    return pts, types, offsets, conn, pd, cd


FIELD = {
    "time": np.array([0.5, 1.25], dtype=np.float64),
    "ids": np.array([[1, 2, 3], [4, 5, 6]], dtype=np.int64),
}


def mixed_piece():
    # A 2x1x1 row of unit cubes (12 points): a hexahedron, a cube cut into two wedges, and
    # above them a pyramid and a tet on 2 extra points.
    pts = [(x, y, z) for z in (0.0, 1.0) for y in (0.0, 1.0) for x in (0.0, 1.0, 2.0)]
    pts += [(0.5, 0.5, 2.0), (1.5, 0.5, 2.0)]
    pts = np.array(pts, dtype=np.float64)

    def p(x, y, z):
        return z * 6 + y * 3 + x

    cells = [
        (12, [p(0, 0, 0), p(1, 0, 0), p(1, 1, 0), p(0, 1, 0), p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1)]),
        (13, [p(1, 0, 0), p(2, 0, 0), p(2, 1, 0), p(1, 0, 1), p(2, 0, 1), p(2, 1, 1)]),
        (13, [p(1, 0, 0), p(2, 1, 0), p(1, 1, 0), p(1, 0, 1), p(2, 1, 1), p(1, 1, 1)]),
        (14, [p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1), 12]),
        (10, [p(1, 0, 1), p(2, 0, 1), p(2, 1, 1), 13]),
    ]
    types = np.array([c[0] for c in cells], dtype=np.uint8)
    conn = np.array([i for c in cells for i in c[1]], dtype=np.int64)
    offsets = np.concatenate([[0], np.cumsum([len(c[1]) for c in cells])]).astype(np.int64)
    pd = {"height": pts[:, 2].astype(np.float64)}
    cd = {"global_id": np.arange(100, 100 + len(cells), dtype=np.uint64),
          "kind": types.astype(np.uint8)}
    return pts, types, offsets, conn, pd, cd


def check_vtk(path):
    """VTK 9.1's reading of path, saved as X_vtk.vtu."""
    r = vtk.vtkHDFReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    if g is None or g.GetNumberOfPoints() == 0:
        raise SystemExit(f"VTK 9.1 could not read {path}")
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetFileName(os.path.splitext(path)[0] + "_vtk.vtu")
    w.SetInputData(g)
    w.SetDataModeToBinary()
    w.SetCompressorTypeToNone()
    w.SetHeaderTypeToUInt64()
    w.Write()
    print(f"{os.path.basename(path)}: VTK 9.1 reads {g.GetNumberOfPoints()} points, "
          f"{g.GetNumberOfCells()} cells, {g.GetPointData().GetNumberOfArrays()} point, "
          f"{g.GetCellData().GetNumberOfArrays()} cell, {g.GetFieldData().GetNumberOfArrays()} field arrays")


def main():
    os.makedirs(OUT, exist_ok=True)
    for f in os.listdir(OUT):
        os.remove(os.path.join(OUT, f))
    o = lambda n: os.path.join(OUT, n)

    good = []
    write(o("tets.vtkhdf"), [tets_piece()], FIELD)
    good.append("tets.vtkhdf")
    write(o("two_pieces.vtkhdf"), [tets_piece(), tets_piece(100.0, (2.0, 0.0, 0.0))], FIELD)
    good.append("two_pieces.vtkhdf")
    pts, types, offsets, conn, _, _ = tets_piece()
    write(o("float32.hdf"), [(pts.astype(np.float32), types, offsets, conn,
                              {"level": (np.arange(len(pts)) * 7 % 65535).astype(np.uint16)},
                              {"sign": ((np.arange(len(types)) % 5) - 2).astype(np.int8)})])
    good.append("float32.hdf")
    write(o("mixed.vtkhdf"), [mixed_piece()], {"note_id": np.array([42], dtype=np.int32)})
    good.append("mixed.vtkhdf")
    write(o("gzip.vtkhdf"), [tets_piece()], FIELD, gzip=True)
    good.append("gzip.vtkhdf")
    # VTK 9.1 reads version 2.0 (without Steps) with a warning that it supports 1.0.
    write(o("version2.vtkhdf"), [tets_piece(dims=(2, 2, 2))], FIELD, version=(2, 0))
    good.append("version2.vtkhdf")
    write(o("userblock.vtkhdf"), [tets_piece(dims=(2, 2, 2))], FIELD, userblock=512)
    good.append("userblock.vtkhdf")
    for name in good:
        check_vtk(o(name))

    # Bad ones, from a 2x2x2 lattice to keep them small.
    small = tets_piece(dims=(2, 2, 2))
    write(o("bad_type.vtkhdf"), [small], dtype_type="ImageData")
    pts, types, offsets, conn, pd, cd = small
    c = conn.copy()
    c[7] = len(pts) + 3
    write(o("bad_connectivity.vtkhdf"), [(pts, types, offsets, c, pd, cd)])
    off = offsets.copy()
    off[2], off[3] = off[3], off[2]
    write(o("bad_offsets.vtkhdf"), [(pts, types, off, conn, pd, cd)])
    # Cell 1 takes one of cell 2's points: a tetra of 5, then one of 3.
    off = offsets.copy()
    off[2] += 1
    write(o("bad_cellsize.vtkhdf"), [(pts, types, off, conn, pd, cd)])
    write(o("bad_points.vtkhdf"), [(pts[:, :2].copy(), types, offsets, conn, pd, cd)])
    pd_short = dict(pd)
    pd_short["temperature"] = pd["temperature"][:-1]
    write(o("bad_pointdata.vtkhdf"), [(pts, types, offsets, conn, pd_short, cd)])
    t = types.copy()
    t[0] = 42
    write(o("polyhedron.vtkhdf"), [(pts, t, offsets, conn, pd, cd)])
    write(o("temporal.vtkhdf"), [small], version=(2, 0))
    with h5py.File(o("temporal.vtkhdf"), "a") as f:
        s = f["VTKHDF"].create_group("Steps")
        s.attrs["NSteps"] = np.int64(1)
        s.create_dataset("Values", data=np.array([0.0]))
    write(o("string_field.vtkhdf"), [small])
    with h5py.File(o("string_field.vtkhdf"), "a") as f:
        f["VTKHDF/FieldData"].create_dataset("names", data=np.array([b"alpha", b"beta"], dtype="S8"))
        f["VTKHDF/FieldData"].create_dataset("vnames", data=["gamma", "d\u00e9lta"],
                                             dtype=h5py.string_dtype())
        # What h5py writes by default: a variable-length UTF-8 Type, an int32 Version; and the
        # active scalars named on PointData as VTK XML names them.
        f["VTKHDF"].attrs["Type"] = "UnstructuredGrid"
        f["VTKHDF"].attrs["Version"] = np.array([1, 0], dtype=np.int32)
        f["VTKHDF/PointData"].attrs["Scalars"] = "temperature"
    with open(o("tets.vtkhdf"), "rb") as f:
        head = f.read(3000)
    with open(o("truncated.vtkhdf"), "wb") as f:
        f.write(head)


if __name__ == "__main__":
    main()
