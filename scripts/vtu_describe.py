#!/usr/bin/python3
"""Reads .vtu/.pvtu files with VTK 9.1 and prints, as JSON keyed by file name, what VTK holds in
memory: counts, and type, components, component names and checksum of every array (the same
description scripts/make_vtk_fixtures.py writes to fixtures/vtk/manifest.json). The interop
test (tests/vtu_vtk_interop.rs) compares it with what tetkit wrote.

Usage: /usr/bin/python3 scripts/vtu_describe.py FILE...
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vtk  # noqa: E402
from make_vtk_fixtures import describe  # noqa: E402

out = {}
for f in sys.argv[1:]:
    r = vtk.vtkXMLPUnstructuredGridReader() if f.endswith(".pvtu") else vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(f)
    r.Update()
    if r.GetErrorCode() != 0:
        out[f] = {"error": f"VTK error code {r.GetErrorCode()}"}
        continue
    out[f] = describe(r.GetOutput())
json.dump(out, sys.stdout)
