#!/usr/bin/python3
"""Times VTK's vtkCellCenterDepthSort on a tet mesh for one camera (the baseline `tetkit` compares
its sorts against). Input: a .vtu file, or raw little-endian arrays written by benches/sort.rs
(POINTS as float64 x,y,z triples and TETS as int64 quadruples). Prints JSON: per-run seconds for
InitTraversal plus draining GetNextCells, and the number of cells returned."""
import argparse
import json
import sys
import time

import numpy as np
import vtk
from vtk.util import numpy_support as ns


def vec3(s):
    v = [float(x) for x in s.split(",")]
    if len(v) != 3:
        raise argparse.ArgumentTypeError(f"'{s}': expected x,y,z")
    return v


def load(args):
    if args.mesh.endswith(".vtu"):
        r = vtk.vtkXMLUnstructuredGridReader()
        r.SetFileName(args.mesh)
        r.Update()
        return r.GetOutput()
    pts = np.fromfile(args.mesh, dtype="<f8").reshape(-1, 3)
    tets = np.fromfile(args.tets, dtype="<i8").reshape(-1, 4)
    ug = vtk.vtkUnstructuredGrid()
    p = vtk.vtkPoints()
    p.SetData(ns.numpy_to_vtk(pts, deep=True))
    ug.SetPoints(p)
    n = tets.shape[0]
    offsets = ns.numpy_to_vtkIdTypeArray(np.arange(0, 4 * n + 1, 4, dtype=np.int64), deep=True)
    conn = ns.numpy_to_vtkIdTypeArray(tets.reshape(-1).astype(np.int64), deep=True)
    cells = vtk.vtkCellArray()
    cells.SetData(offsets, conn)
    ug.SetCells(vtk.VTK_TETRA, cells)
    return ug


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("mesh", help=".vtu file, or raw float64 points file")
    ap.add_argument("tets", nargs="?", help="raw int64 tets file (with raw points)")
    ap.add_argument("--position", type=vec3, required=True)
    ap.add_argument("--focal", type=vec3, required=True)
    ap.add_argument("--up", type=vec3, default=[0.0, 0.0, 1.0])
    ap.add_argument("--parallel", action="store_true")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    if not args.mesh.endswith(".vtu") and not args.tets:
        ap.error("raw input needs both POINTS and TETS files")
    ug = load(args)
    cam = vtk.vtkCamera()
    cam.SetPosition(*args.position)
    cam.SetFocalPoint(*args.focal)
    cam.SetViewUp(*args.up)
    cam.SetParallelProjection(1 if args.parallel else 0)
    times = []
    count = 0
    for _ in range(max(1, args.repeat)):
        sort = vtk.vtkCellCenterDepthSort()
        sort.SetInput(ug)
        sort.SetCamera(cam)
        sort.SetModelTransform(vtk.vtkTransform().GetMatrix())
        sort.SetDirectionToBackToFront()
        t0 = time.perf_counter()
        sort.InitTraversal()
        count = 0
        while True:
            ids = sort.GetNextCells()
            if ids is None:
                break
            count += ids.GetNumberOfTuples()
        times.append(time.perf_counter() - t0)
    json.dump({"cells": ug.GetNumberOfCells(), "sorted": count, "seconds": times,
               "vtk": vtk.vtkVersion.GetVTKVersion()}, sys.stdout)
    print()


if __name__ == "__main__":
    main()
