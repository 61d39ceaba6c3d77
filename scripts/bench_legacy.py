#!/usr/bin/python3
"""Times VTK 9.1 and tetkit on the same legacy files in the same run.

The mesh is the issue's benchmark: a 100^3-point image grid cut into 4.85M tets by VTK's
vtkDataSetTriangleFilter, with 3 arrays (point scalars, point vectors, cell ids). VTK writes it
as legacy 5.1 and 4.2 binary (those writes are VTK's write times); then VTK reads each file and
`tetkit bench legacy` reads and writes each, best of --repeat runs each.

Usage: scripts/bench_legacy.py [--dir /tmp/tetkit-bench] [--repeat 3] [--tetkit target/release/tetkit]
"""
import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np
import vtk
from vtk.util.numpy_support import numpy_to_vtk


def make_mesh(n=100):
    img = vtk.vtkImageData()
    img.SetDimensions(n, n, n)
    img.SetSpacing(1.0 / (n - 1), 1.0 / (n - 1), 1.0 / (n - 1))
    x = np.linspace(0, 1, n, dtype=np.float32)
    zz, yy, xx = np.meshgrid(x, x, x, indexing="ij")
    s = (np.sin(6 * xx) * np.cos(5 * yy) + zz).astype(np.float32).ravel()
    a = numpy_to_vtk(s, deep=1)
    a.SetName("scalars")
    img.GetPointData().SetScalars(a)
    v = np.stack([xx.ravel(), yy.ravel(), zz.ravel()], axis=1).astype(np.float32)
    b = numpy_to_vtk(v, deep=1)
    b.SetName("vectors")
    img.GetPointData().SetVectors(b)
    c = numpy_to_vtk(np.arange((n - 1) ** 3, dtype=np.int32), deep=1)
    c.SetName("cell_id")
    img.GetCellData().AddArray(c)
    tri = vtk.vtkDataSetTriangleFilter()
    tri.SetInputData(img)
    tri.Update()
    return tri.GetOutput()


def best(fn, repeat):
    times = []
    out = None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return min(times), out


def vtk_write(grid, path, version, repeat):
    def go():
        w = vtk.vtkUnstructuredGridWriter()
        w.SetInputData(grid)
        w.SetFileName(path)
        w.SetFileVersion(version)
        w.SetFileTypeToBinary()
        if not w.Write():
            sys.exit(f"VTK failed to write {path}")
    return best(go, repeat)[0]


def vtk_read(path, repeat):
    def go():
        r = vtk.vtkUnstructuredGridReader()
        r.SetFileName(path)
        r.ReadAllScalarsOn()
        r.ReadAllVectorsOn()
        r.ReadAllFieldsOn()
        r.Update()
        g = r.GetOutput()
        return g.GetNumberOfPoints(), g.GetNumberOfCells()
    return best(go, repeat)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dir", default="/tmp/tetkit-bench")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--tetkit", default=os.path.join(os.path.dirname(__file__), "..", "target", "release", "tetkit"))
    args = ap.parse_args()
    os.makedirs(args.dir, exist_ok=True)
    t = time.perf_counter()
    grid = make_mesh()
    print(f"mesh: {grid.GetNumberOfPoints()} points, {grid.GetNumberOfCells()} tets "
          f"({time.perf_counter() - t:.1f} s to make)", flush=True)
    rows = []
    for version, name in ((51, "5.1"), (42, "4.2")):
        path = os.path.join(args.dir, f"bench_{version}_binary.vtk")
        vw = vtk_write(grid, path, version, args.repeat)
        vr, counts = vtk_read(path, args.repeat)
        out = subprocess.run([args.tetkit, "bench", "legacy", path, "--repeat", str(args.repeat),
                              "--dir", args.dir, "--json"], capture_output=True, text=True)
        if out.returncode != 0:
            sys.exit(f"tetkit bench legacy failed: {out.stderr}")
        tk = json.loads(out.stdout)
        if (tk["points"], tk["cells"]) != counts:
            sys.exit(f"counts differ: VTK {counts}, tetkit {(tk['points'], tk['cells'])}")
        steps = {s["name"]: s["best_s"] for s in tk["steps"]}
        rows.append((name, os.path.getsize(path), vr, steps["read input"], vw,
                     steps[f"write {name} binary"]))
    del grid
    print(f"\nbest of {args.repeat}, seconds, same machine, same run")
    print(f"{'file':<14}{'MB':>8}{'VTK read':>10}{'tetkit read':>13}{'VTK write':>11}{'tetkit write':>14}")
    for name, size, vr, tr, vw, tw in rows:
        print(f"{name + ' binary':<14}{size / 1e6:>8.0f}{vr:>10.3f}{tr:>13.3f}{vw:>11.3f}{tw:>14.3f}")


if __name__ == "__main__":
    main()
