#!/usr/bin/python3
"""I/O benchmark: makes the 4.85M-tet mesh (a 100^3-point image grid cut into tets by VTK's
vtkDataSetTriangleFilter: 1M points, 3 arrays), writes it as appended raw and zlib .vtu with VTK
9.1, times VTK reading and writing both, then runs `tetkit bench io` on the same files in the same
run and prints both side by side.

Usage: /usr/bin/python3 scripts/bench_io.py [--dir DIR] [--tetkit PATH] [--repeat N]
(default DIR /tmp/tetkit-bench-io, PATH target/release/tetkit; build it with cargo build --release)
"""
import argparse
import json
import os
import subprocess
import time

import vtk
from vtk.util import numpy_support as ns
import numpy as np


def make_mesh():
    src = vtk.vtkRTAnalyticSource()  # 100^3 points, point scalars RTData (Float32)
    src.SetWholeExtent(0, 99, 0, 99, 0, 99)
    tri = vtk.vtkDataSetTriangleFilter()
    tri.SetInputConnection(src.GetOutputPort())
    tri.Update()
    ug = tri.GetOutput()
    pts = ns.vtk_to_numpy(ug.GetPoints().GetData())
    vel = ns.numpy_to_vtk(np.ascontiguousarray(np.stack([pts[:, 1], -pts[:, 0], 0.1 * pts[:, 2]], 1).astype(np.float32)), deep=1)
    vel.SetName("velocity")
    ug.GetPointData().AddArray(vel)
    region = ns.numpy_to_vtk((np.arange(ug.GetNumberOfCells()) % 7).astype(np.int32), deep=1)
    region.SetName("region")
    ug.GetCellData().AddArray(region)
    return ug


def vtk_write(ug, path, zlib):
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetInputData(ug)
    w.SetFileName(path)
    w.SetDataModeToAppended()
    w.SetEncodeAppendedData(False)
    w.SetHeaderTypeToUInt64()
    if zlib:
        w.SetCompressorTypeToZLib()
    else:
        w.SetCompressorTypeToNone()
    t = time.perf_counter()
    w.Write()
    return time.perf_counter() - t


def vtk_read(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    t = time.perf_counter()
    r.Update()
    dt = time.perf_counter() - t
    assert r.GetOutput().GetNumberOfCells() > 0
    return dt


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dir", default="/tmp/tetkit-bench-io")
    ap.add_argument("--tetkit", default=os.path.join(os.path.dirname(__file__), "..", "target", "release", "tetkit"))
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    os.makedirs(a.dir, exist_ok=True)
    raw = os.path.join(a.dir, "vtk_raw.vtu")
    zl = os.path.join(a.dir, "vtk_zlib.vtu")
    ug = make_mesh()
    print(f"mesh: {ug.GetNumberOfPoints()} points, {ug.GetNumberOfCells()} cells, "
          f"{ug.GetPointData().GetNumberOfArrays() + ug.GetCellData().GetNumberOfArrays()} arrays")
    vtk_times = {
        "write appended raw": min(vtk_write(ug, raw, False) for _ in range(a.repeat)),
        "write appended zlib": min(vtk_write(ug, zl, True) for _ in range(a.repeat)),
    }
    del ug
    vtk_times["read appended raw"] = min(vtk_read(raw) for _ in range(a.repeat))
    vtk_times["read appended zlib"] = min(vtk_read(zl) for _ in range(a.repeat))
    # tetkit reads VTK's raw file first, then writes its own raw and zlib files and reads those.
    out = subprocess.run([a.tetkit, "bench", "io", raw, "--dir", a.dir, "--repeat", str(a.repeat), "--json"],
                         check=True, capture_output=True, text=True).stdout
    tk = json.loads(out)
    steps = {s["name"]: s for s in tk["steps"]}
    steps["read appended raw (VTK's file)"] = steps.pop("read input")
    vtk_times["read appended raw (VTK's file)"] = vtk_times["read appended raw"]
    mesh = tk["mesh_bytes"]
    print(f"in-memory mesh: {mesh / 1e6:.1f} MB; tetkit threads: {tk['threads']}")
    print(f"{'step':<32} {'VTK s':>8} {'tetkit s':>9} {'speed-up':>9} {'tetkit peak RSS/mesh':>21}")
    for name in ["read appended raw (VTK's file)", "read appended raw", "write appended raw",
                 "read appended zlib", "write appended zlib"]:
        s = steps[name]
        v = vtk_times[name]
        peak = s["peak_rss_bytes"]
        ratio = f"{peak / mesh:.2f}" if peak is not None else "-"
        print(f"{name:<32} {v:>8.3f} {s['seconds']:>9.3f} {v / s['seconds']:>8.2f}x {ratio:>21}")


if __name__ == "__main__":
    main()
