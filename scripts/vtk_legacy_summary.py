#!/usr/bin/python3
"""What VTK 9.1 reads from legacy .vtk files, as JSON: counts, cell types, a connectivity sum, and
per array its type, components, tuples, component names and sums (strings verbatim). Used by
make_legacy_fixtures.py (fixtures/legacy/checksums.json) and by tests/legacy_vtk_interop.rs on
tetkit's outputs. Usage: vtk_legacy_summary.py FILE... (prints {file: summary})."""
import json
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy


def array_summary(a):
    """Type, components, tuples, component names and a sum over the finite values."""
    if isinstance(a, vtk.vtkStringArray) or a.IsA("vtkStringArray"):
        vals = [a.GetValue(i) for i in range(a.GetNumberOfValues())]
        return {"type": "String", "components": a.GetNumberOfComponents(),
                "tuples": a.GetNumberOfTuples(), "strings": vals}
    if a.GetDataType() == vtk.VTK_BIT:
        v = np.array([a.GetValue(i) for i in range(a.GetNumberOfValues())], dtype=np.float64)
    else:
        v = vtk_to_numpy(a).astype(np.float64).ravel()
    fin = v[np.isfinite(v)]
    names = [a.GetComponentName(k) or "" for k in range(a.GetNumberOfComponents())]
    return {"type": a.GetDataTypeAsString(), "components": a.GetNumberOfComponents(),
            "tuples": a.GetNumberOfTuples(), "sum": float(fin.sum()),
            "abs_sum": float(np.abs(fin).sum()), "nonfinite": int(v.size - fin.size),
            "component_names": names if any(names) else []}


def summarize(path):
    r = vtk.vtkUnstructuredGridReader()
    r.SetFileName(path)
    r.ReadAllScalarsOn()
    r.ReadAllVectorsOn()
    r.ReadAllNormalsOn()
    r.ReadAllTensorsOn()
    r.ReadAllTCoordsOn()
    r.ReadAllFieldsOn()
    r.ReadAllColorScalarsOn()
    r.Update()
    g = r.GetOutput()
    out = {"points": g.GetNumberOfPoints(), "cells": g.GetNumberOfCells()}
    if g.GetNumberOfPoints():
        out["points_sum"] = float(vtk_to_numpy(g.GetPoints().GetData()).astype(np.float64).sum())
    types = {}
    for i in range(g.GetNumberOfCells()):
        t = g.GetCellType(i)
        types[str(t)] = types.get(str(t), 0) + 1
    out["cell_types"] = types
    ids = vtk.vtkIdList()
    conn = 0
    for i in range(g.GetNumberOfCells()):
        g.GetCellPoints(i, ids)
        conn += sum(ids.GetId(k) for k in range(ids.GetNumberOfIds()))
    out["connectivity_sum"] = conn
    for key, data in (("point_data", g.GetPointData()), ("cell_data", g.GetCellData()),
                      ("field_data", g.GetFieldData())):
        out[key] = {}
        for k in range(data.GetNumberOfArrays()):
            a = data.GetAbstractArray(k)
            out[key][a.GetName()] = array_summary(a)
    for key, data in (("point_active", g.GetPointData()), ("cell_active", g.GetCellData())):
        act = {}
        for role, get in (("Scalars", data.GetScalars), ("Vectors", data.GetVectors),
                          ("Normals", data.GetNormals), ("Tensors", data.GetTensors),
                          ("TCoords", data.GetTCoords), ("GlobalIds", data.GetGlobalIds),
                          ("PedigreeIds", data.GetPedigreeIds)):
            a = get()
            if a is not None:
                act[role] = a.GetName()
        out[key] = act
    return out


if __name__ == "__main__":
    vtk.vtkObject.GlobalWarningDisplayOff()
    print(json.dumps({p: summarize(p) for p in sys.argv[1:]}, sort_keys=True))
