#!/usr/bin/env bash
# Writes the NetCDF-4 (HDF5) Exodus II fixtures in fixtures/exodus/nc4/, for the tests that read
# them exactly as their classic originals in fixtures/exodus/:
#   X.exo      nccopy -k nc4 -d 1 -s: netCDF-4, chunked, deflate + shuffle
#   X_nc7.exo  nccopy -k nc7: netCDF-4 classic model (HDF5, classic types only)
#   meshio.exo, meshio_strings.exo, meshio_cdf5.exo: a mesh written the way meshio writes Exodus
#     (netCDF4-python, NETCDF4, int64 connectivity and node sets, an unlimited time_step, char
#     names), the same with its names as NC_STRING, and its classic CDF-5 copy (nccopy -k cdf5);
#   not_exodus.nc: a NetCDF-4 file that is not Exodus II, for the refusal.
#
# Only for regenerating the fixtures: needs netcdf-bin (nccopy) and python3-netcdf4, Debian
# packages that neither building tetkit (its NetCDF-4 reader is pure Rust) nor its tests need.
#   apt-get install -y netcdf-bin python3-netcdf4 && scripts/make_exodus_nc4_fixtures.sh
# Run after scripts/make_exodus_fixtures.py, which writes the classic originals.
set -euo pipefail
cd "$(dirname "$0")/../fixtures/exodus"
mkdir -p nc4
rm -f nc4/*.exo nc4/*.nc
# hand5.exo is hand.exo in CDF-5: its netCDF-4 copy would be the same file.
for f in hand mixed quadratic steps tets; do
    nccopy -k nc4 -d 1 -s "$f.exo" "nc4/$f.exo"
done
for f in steps tets; do
    nccopy -k nc7 "$f.exo" "nc4/${f}_nc7.exo"
done

/usr/bin/python3 - <<'PY'
import netCDF4
import numpy as np

# Two tetrahedra and a hexahedron in two blocks, as meshio's exodus writer (meshio 5) lays them
# out: int64 connectivity, eb_prop1 numbering blocks from 0, a float32 time_whole with one step.
points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1],
                   [2, 0, 0], [3, 0, 0], [3, 1, 0], [2, 1, 0],
                   [2, 0, 1], [3, 0, 1], [3, 1, 1], [2, 1, 1]], dtype=np.float64)
blocks = [("TETRA", np.array([[0, 1, 2, 3], [1, 2, 3, 4]], dtype=np.int64)),
          ("HEX", np.array([[5, 6, 7, 8, 9, 10, 11, 12]], dtype=np.int64))]
temperature = points[:, 0] * 10 + points[:, 2]
bottom = np.array([0, 1, 2, 5, 6, 7, 8], dtype=np.int64)


def write(path, strings):
    with netCDF4.Dataset(path, "w", format="NETCDF4") as g:
        g.title = "Created like meshio's exodus writer"
        g.version = np.float32(5.1)
        g.api_version = np.float32(5.1)
        g.floating_point_word_size = 8
        g.createDimension("num_nodes", len(points))
        g.createDimension("num_dim", 3)
        g.createDimension("num_elem", sum(len(c) for _, c in blocks))
        g.createDimension("num_el_blk", len(blocks))
        g.createDimension("num_node_sets", 1)
        g.createDimension("len_string", 33)
        g.createDimension("len_line", 81)
        g.createDimension("four", 4)
        g.createDimension("time_step", None)
        g.createVariable("time_whole", "f4", ("time_step",))[:] = 0.0

        def names(var, dim, values):
            if strings:
                v = g.createVariable(var, str, (dim,))
                for k, s in enumerate(values):
                    v[k] = s
            else:
                v = g.createVariable(var, "S1", (dim, "len_string"))
                v.set_auto_mask(False)
                for k, s in enumerate(values):
                    v[k, :len(s)] = netCDF4.stringtochar(np.array([s], "S%d" % len(s)))[0]

        names("coor_names", "num_dim", ["X", "Y", "Z"])
        for k, axis in enumerate("xyz"):
            g.createVariable("coord" + axis, "f8", ("num_nodes",))[:] = points[:, k]
        g.createVariable("eb_prop1", "i4", "num_el_blk")[:] = np.arange(len(blocks))
        for k, (kind, cells) in enumerate(blocks):
            g.createDimension(f"num_el_in_blk{k + 1}", cells.shape[0])
            g.createDimension(f"num_nod_per_el{k + 1}", cells.shape[1])
            v = g.createVariable(f"connect{k + 1}", "i8",
                                 (f"num_el_in_blk{k + 1}", f"num_nod_per_el{k + 1}"))
            v.elem_type = kind
            v[:] = cells + 1
        g.createDimension("num_nod_var", 1)
        names("name_nod_var", "num_nod_var", ["temperature"])
        g.createVariable("vals_nod_var1", "f8", ("time_step", "num_nodes"))[0] = temperature
        g.createVariable("ns_prop1", "i4", "num_node_sets")[:] = [0]
        names("ns_names", "num_node_sets", ["bottom"])
        g.createDimension("num_nod_ns1", len(bottom))
        g.createVariable("node_ns1", "i8", ("num_nod_ns1",))[:] = bottom + 1


write("nc4/meshio.exo", False)
write("nc4/meshio_strings.exo", True)

# A NetCDF-4 file that is not Exodus II, for the refusal.
with netCDF4.Dataset("nc4/not_exodus.nc", "w", format="NETCDF4") as g:
    g.createDimension("x", 4)
    g.createVariable("temperature", "f4", ("x",))[:] = [1, 2, 3, 4]
PY
nccopy -k cdf5 nc4/meshio.exo nc4/meshio_cdf5.exo
ls -l nc4
