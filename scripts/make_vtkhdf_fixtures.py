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
  bad_steps.vtkhdf         a Steps group with NSteps and Values only (no PartOffsets, ...)
  bad_step_offsets.vtkhdf  temporal.vtkhdf with step 0's PointOffsets past the Points
  truncated.vtkhdf         tets.vtkhdf cut to its first 3000 bytes
Temporal (VTKHDF 2.0, a Steps group; VTK 9.1 predates temporal VTKHDF, so no VTK reading):
  temporal.vtkhdf          4 steps laid out as VTK's vtkHDFWriter lays them out: geometry
                           written when it changes (steps 0-1: one part; steps 2-3: two parts),
                           point and cell data each step with Steps/PointDataOffsets and
                           CellDataOffsets (step 3's 'temperature' replays step 2's rows), a
                           field array with FieldDataOffsets/FieldDataSizes (none at step 2),
                           CellOffsets N x 1 and ConnectivityIdOffsets 1-D
  temporal_gzip.vtkhdf     the same, its datasets deflated in chunks of 4 rows
  temporal_stepK.vtkhdf    step K of temporal.vtkhdf as a static file, built from the same
                           numpy arrays without the Steps layout: what reading temporal@K gives
                           (besides the field array Time)
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


def write_temporal(path, steps, gzip=False):
    """steps: dicts with 'time', 'geom' (list of (points, types, offsets, connectivity) parts, or
    None to keep the previous step's), 'pd' and 'cd' (name -> the step's values, parts
    concatenated), 'replay' (point arrays that reuse the previous step's rows) and 'field'
    (name -> 2-D values; a name missing from a step has size 0 there). With gzip, the mesh and
    array datasets are deflated in chunks of 4 rows, so a step's rows start and end inside
    chunks."""
    def ds(group, name, data):
        if gzip:
            group.create_dataset(name, data=data, compression="gzip", compression_opts=6,
                                 chunks=(4,) + data.shape[1:])
        else:
            group.create_dataset(name, data=data)

    with h5py.File(path, "w") as f:
        root = f.create_group("VTKHDF")
        root.attrs["Version"] = np.array((2, 0), dtype=np.int64)
        root.attrs.create("Type", np.bytes_("UnstructuredGrid"),
                          dtype=h5py.string_dtype("ascii", len("UnstructuredGrid")))
        counts = {"NumberOfPoints": [], "NumberOfCells": [], "NumberOfConnectivityIds": []}
        geo = {"Points": [], "Types": [], "Offsets": [], "Connectivity": []}
        st = {k: [] for k in ("PartOffsets", "NumberOfParts", "PointOffsets", "CellOffsets",
                              "ConnectivityIdOffsets")}
        rows = {"PointData": {}, "CellData": {}, "FieldData": {}}
        offs = {"PointData": {}, "CellData": {}, "FieldData": {}}
        sizes = {}
        fnames = sorted({n for s in steps for n in s["field"]})
        cur = None
        for s in steps:
            if s["geom"] is not None:
                # In the order of `st`: PartOffsets, NumberOfParts, PointOffsets, CellOffsets,
                # ConnectivityIdOffsets.
                cur = (len(counts["NumberOfPoints"]), len(s["geom"]), sum(counts["NumberOfPoints"]),
                       sum(counts["NumberOfCells"]), sum(counts["NumberOfConnectivityIds"]))
                for pts, types, offsets, conn in s["geom"]:
                    counts["NumberOfPoints"].append(len(pts))
                    counts["NumberOfCells"].append(len(types))
                    counts["NumberOfConnectivityIds"].append(len(conn))
                    for k, v in zip(("Points", "Types", "Offsets", "Connectivity"),
                                    (pts, types, offsets, conn)):
                        geo[k].append(v)
            for k, v in zip(st, cur):
                st[k].append(v)
            for g, key in (("PointData", "pd"), ("CellData", "cd")):
                for name, v in s[key].items():
                    r, o = rows[g].setdefault(name, []), offs[g].setdefault(name, [])
                    if name in s.get("replay", ()):
                        o.append(o[-1])
                    else:
                        o.append(sum(len(x) for x in r))
                        r.append(v)
            for name in fnames:
                r, o = rows["FieldData"].setdefault(name, []), offs["FieldData"].setdefault(name, [])
                o.append(sum(len(x) for x in r))
                v = s["field"].get(name)
                if v is None:
                    sizes.setdefault(name, []).append((0, 0))
                else:
                    sizes.setdefault(name, []).append((v.shape[1], v.shape[0]))
                    r.append(v)
        for k, v in counts.items():
            root.create_dataset(k, data=np.array(v, dtype=np.int64))
        for k, v in geo.items():
            ds(root, k, np.concatenate(v))
        for g in rows:
            grp = root.create_group(g)
            for name, r in rows[g].items():
                ds(grp, name, np.concatenate(r))
        steps_g = root.create_group("Steps")
        steps_g.attrs["NSteps"] = np.int64(len(steps))
        steps_g.create_dataset("Values", data=np.array([s["time"] for s in steps], dtype=np.float64))
        for k, v in st.items():
            v = np.array(v, dtype=np.int64)
            # Both shapes VTK writes for an UnstructuredGrid: N x 1 and 1-D.
            steps_g.create_dataset(k, data=v.reshape(-1, 1) if k == "CellOffsets" else v)
        for g, kind in (("PointData", "PointDataOffsets"), ("CellData", "CellDataOffsets"),
                        ("FieldData", "FieldDataOffsets")):
            grp = steps_g.create_group(kind)
            for name, o in offs[g].items():
                grp.create_dataset(name, data=np.array(o, dtype=np.int64))
        grp = steps_g.create_group("FieldDataSizes")
        for name, v in sizes.items():
            grp.create_dataset(name, data=np.array(v, dtype=np.int64))


def temporal_steps():
    """The steps of temporal.vtkhdf, and each as the pieces and field of a static file."""
    a = [tets_piece(dims=(2, 2, 2))]
    b = [tets_piece(dims=(2, 2, 2), origin=(1.0, 0.0, 0.0)),
         tets_piece(dims=(3, 2, 2), origin=(0.0, 2.0, 0.0))]
    geom = [a, a, b, b]
    out, static = [], []
    for k, time in enumerate((0.0, 0.5, 1.25, 2.0)):
        parts = geom[k]
        pds, cds = [], []
        for pts, types, _, _, _, _ in parts:
            pd, cd, _ = piece_arrays(pts, len(types), shift=10.0 * k)
            pds.append(pd)
            cds.append(cd)
        pd = {n: np.concatenate([x[n] for x in pds]) for n in pds[0]}
        cd = {n: np.concatenate([x[n] for x in cds]) for n in cds[0]}
        replay = ()
        if k == 3:
            # temperature replays step 2's rows.
            pd["temperature"] = out[2]["pd"]["temperature"]
            replay = ("temperature",)
        field = {}
        if k != 2:
            field["history"] = (np.arange((k + 1) * 2, dtype=np.float64) * 0.5 + k).reshape(k + 1, 2)
        out.append({"time": time, "geom": [p[:4] for p in parts] if k in (0, 2) else None,
                    "pd": pd, "cd": cd, "replay": replay, "field": field})
        # The static file's pieces carry their own slices of the step's arrays.
        pieces, p0, c0 = [], 0, 0
        for pts, types, offsets, conn, _, _ in parts:
            pieces.append((pts, types, offsets, conn,
                           {n: v[p0:p0 + len(pts)] for n, v in pd.items()},
                           {n: v[c0:c0 + len(types)] for n, v in cd.items()}))
            p0 += len(pts)
            c0 += len(types)
        static.append((pieces, field))
    return out, static


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
    write(o("bad_steps.vtkhdf"), [small], version=(2, 0))
    with h5py.File(o("bad_steps.vtkhdf"), "a") as f:
        s = f["VTKHDF"].create_group("Steps")
        s.attrs["NSteps"] = np.int64(1)
        s.create_dataset("Values", data=np.array([0.0]))
    steps, static = temporal_steps()
    write_temporal(o("temporal.vtkhdf"), steps)
    write_temporal(o("temporal_gzip.vtkhdf"), steps, gzip=True)
    for k, (pieces, field) in enumerate(static):
        write(o(f"temporal_step{k}.vtkhdf"), pieces, field, version=(2, 0))
    write_temporal(o("bad_step_offsets.vtkhdf"), steps)
    with h5py.File(o("bad_step_offsets.vtkhdf"), "a") as f:
        f["VTKHDF/Steps/PointOffsets"][0] = 1000
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
