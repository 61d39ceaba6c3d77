#!/usr/bin/python3
"""Per-frame render time of tetkit against VTK 9.1, same mesh, view and image size, same run.

For each size the script builds a tetrahedralized grid with VTK (vtkImageData through
vtkDataSetTriangleFilter, point scalar x + 2y + 3z scaled to [0, 1]), writes it as legacy binary
VTK, and times:
  - VTK's vtkProjectedTetrahedraMapper (centroid sort, no pre-integration),
  - VTK's vtkUnstructuredGridVolumeRayCastMapper (Bunyk, exact order),
  - tetkit render --sort kd --integration preintegrated (exact PT),
  - tetkit render --sort centroid --integration average (what VTK's PT does),
  - tetkit render --method raycast (the exact reference),
  - tetkit render --method raycast --ray-integration preintegrated (segments from the table, as
    VTK's ray caster integrates them).
Per-frame time is the median over frames after a 2-degree turn each (setup excluded: VTK's first
render, tetkit's read/adjacency/table setup, which tetkit reports separately).

Fairness: VTK's frame time includes its sort and a glFinish (WaitForCompletion), so no queued
rasterization is left out; the ray caster's automatic image-sample-distance adjustment is off (it
would render fewer rays); the window size is checked; and the coverage (share of non-background
pixels) of each VTK image and of tetkit's last frame is printed, so a renderer that skipped part of
the volume would show. The machine may be shared: every measurement is repeated --rounds times,
VTK and tetkit interleaved, and the fastest round's median is kept (contention only adds time).

With --torus MAXVOL it also times a TetGen mesh of the torus of scripts/tetgen_surfaces.py
(`tetgen -pq1.2aMAXVOL`; 0.00006 gives about 200k tets, near the issue's 211k-tet torus),
converted with tetkit, with the same scalar (x + 2y + 3z over its bounds, scaled to [0, 1]) and a
fifth of its diagonal as unit distance: a non-convex mesh from a real mesher, not a grid.

VTK needs an X server here:  xvfb-run -a scripts/bench_render_vtk.py --tets 200000 1000000
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

import vtk
from vtk.util.numpy_support import numpy_to_vtk, vtk_to_numpy

COOL_TO_WARM = [
    [0.230, 0.299, 0.754], [0.375, 0.486, 0.904], [0.552, 0.690, 0.996],
    [0.720, 0.831, 0.996], [0.865, 0.865, 0.865], [0.957, 0.769, 0.678],
    [0.969, 0.605, 0.481], [0.882, 0.373, 0.298], [0.706, 0.016, 0.150],
]


def write_legacy(ug, path):
    w = vtk.vtkUnstructuredGridWriter()
    w.SetFileTypeToBinary()
    w.SetFileName(path)
    w.SetInputData(ug)
    w.Write()


def make_mesh(target_tets, path):
    # vtkDataSetTriangleFilter cuts each voxel of image data into 5 tets.
    n = max(1, round((target_tets / 5.0) ** (1.0 / 3.0)))
    img = vtk.vtkImageData()
    img.SetDimensions(n + 1, n + 1, n + 1)
    img.SetSpacing(1.0 / n, 1.0 / n, 1.0 / n)
    img.SetOrigin(0.0, 0.0, 0.0)
    arr = vtk.vtkDoubleArray()
    arr.SetName("scalar")
    arr.SetNumberOfTuples(img.GetNumberOfPoints())
    for i in range(img.GetNumberOfPoints()):
        x, y, z = img.GetPoint(i)
        arr.SetValue(i, (x + 2 * y + 3 * z) / 6.0)
    img.GetPointData().SetScalars(arr)
    tri = vtk.vtkDataSetTriangleFilter()
    tri.SetInputData(img)
    tri.TetrahedraOnlyOn()
    tri.Update()
    ug = tri.GetOutput()
    ug.GetPointData().SetActiveScalars("scalar")
    write_legacy(ug, path)
    return ug


def make_torus(max_volume, tmp, exe, path):
    """A TetGen torus (see the module doc), written as legacy binary VTK with a point scalar."""
    here = os.path.dirname(os.path.abspath(__file__))
    subprocess.run([sys.executable, os.path.join(here, "tetgen_surfaces.py"), tmp], check=True,
                   capture_output=True)
    subprocess.run(["tetgen", f"-pq1.2a{max_volume}zQ", "torus.poly"], cwd=tmp, check=True,
                   capture_output=True)
    # Only the tets: tetkit's convert also reads the boundary triangles of torus.1.face, which
    # VTK's PT mapper refuses (it draws nothing for a mesh that is not all tetrahedra).
    for ext in ("face", "edge"):
        if os.path.exists(os.path.join(tmp, f"torus.1.{ext}")):
            os.remove(os.path.join(tmp, f"torus.1.{ext}"))
    vtu = os.path.join(tmp, "torus.vtu")
    subprocess.run([exe, "convert", os.path.join(tmp, "torus.1.ele"), vtu], check=True,
                   capture_output=True)
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(vtu)
    r.Update()
    ug = r.GetOutput()
    pts = vtk_to_numpy(ug.GetPoints().GetData())
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    v = (pts - lo) / (hi - lo)
    s = (v[:, 0] + 2 * v[:, 1] + 3 * v[:, 2]) / 6.0
    arr = numpy_to_vtk(s.astype("float64"), deep=1)
    arr.SetName("scalar")
    ug.GetPointData().AddArray(arr)
    ug.GetPointData().SetActiveScalars("scalar")
    write_legacy(ug, path)
    diag = float(((hi - lo) ** 2).sum() ** 0.5)
    return ug, diag


def coverage(img):
    """Share of pixels of a vtkImageData whose RGB is not black."""
    a = vtk_to_numpy(img.GetPointData().GetScalars())
    return float((a[:, :3].max(axis=1) > 0).mean())


def png_coverage(path):
    r = vtk.vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    return coverage(r.GetOutput())


def vtk_time(ug, kind, frames, size, unit_distance):
    if kind == "pt":
        mapper = vtk.vtkProjectedTetrahedraMapper()
    else:
        mapper = vtk.vtkUnstructuredGridVolumeRayCastMapper()
        # One ray per pixel, whatever the frame time (the default may render fewer rays).
        mapper.SetAutoAdjustSampleDistances(0)
        mapper.SetImageSampleDistance(1.0)
    mapper.SetInputData(ug)
    ctf = vtk.vtkColorTransferFunction()
    for i, c in enumerate(COOL_TO_WARM):
        ctf.AddRGBPoint(i / (len(COOL_TO_WARM) - 1), *c)
    otf = vtk.vtkPiecewiseFunction()
    otf.AddPoint(0.0, 0.0)
    otf.AddPoint(1.0, 1.0)
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(ctf)
    prop.SetScalarOpacity(otf)
    prop.SetScalarOpacityUnitDistance(unit_distance)
    prop.SetInterpolationTypeToLinear()
    vol = vtk.vtkVolume()
    vol.SetMapper(mapper)
    vol.SetProperty(prop)
    ren = vtk.vtkRenderer()
    ren.AddVolume(vol)
    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetSize(size, size)
    win.AddRenderer(ren)
    ren.ResetCamera()
    cam = ren.GetActiveCamera()
    # tetkit's --orbit turns about the view-up before elevation (a turntable): the same here.
    up0 = cam.GetViewUp()
    cam.Azimuth(30)
    cam.Elevation(20)
    cam.OrthogonalizeViewUp()
    ren.ResetCameraClippingRange()
    t0 = time.perf_counter()
    win.Render()
    win.WaitForCompletion()
    first = time.perf_counter() - t0
    if tuple(win.GetSize()) != (size, size):
        sys.exit(f"VTK window is {win.GetSize()}, not {size}x{size}")
    times = []
    for _ in range(frames):
        fp = cam.GetFocalPoint()
        turn = vtk.vtkTransform()
        turn.Translate(*fp)
        turn.RotateWXYZ(2, *up0)
        turn.Translate(*[-x for x in fp])
        cam.SetPosition(turn.TransformPoint(cam.GetPosition()))
        cam.SetViewUp(turn.TransformVector(cam.GetViewUp()))
        ren.ResetCameraClippingRange()
        t0 = time.perf_counter()
        win.Render()
        win.WaitForCompletion()
        times.append(time.perf_counter() - t0)
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(win)
    grab.ShouldRerenderOff()
    grab.ReadFrontBufferOff()
    grab.Update()
    return first, statistics.median(times), coverage(grab.GetOutput())


FRAME = re.compile(r"^frame (\d+): ([0-9.]+) s")
SETUP = re.compile(r"setup \([^)]*\) ([0-9.]+) s")


def tetkit_time(exe, mesh, out_png, frames, size, unit_distance, extra):
    cmd = [exe, "render", mesh, "-o", out_png, "--size", f"{size}x{size}",
           "--azimuth", "30", "--elevation", "20", "--colormap", "cool-to-warm",
           "--opacity", "ramp", "--unit-distance", repr(unit_distance),
           "--orbit", str(frames + 1), "--orbit-step", "2"] + extra
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"tetkit failed: {' '.join(cmd)}\n{p.stderr}")
    times = [float(m.group(2)) for m in map(FRAME.match, p.stderr.splitlines()) if m]
    setup = [float(m.group(1)) for m in map(SETUP.search, p.stderr.splitlines()) if m]
    # Frame 0 is the first view; the turned frames after it are what an orbit costs.
    last = out_png[:-4] + f"_{frames:04d}.png"
    return (setup[0] if setup else float("nan")), statistics.median(times[1:] or times), png_coverage(last)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tets", type=int, nargs="*", default=[200000, 1000000], help="grid sizes (none: only --torus)")
    ap.add_argument("--frames", type=int, default=3)
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--tetkit", default=os.path.join(os.path.dirname(__file__), "..", "target", "release", "tetkit"))
    ap.add_argument("--no-vtk-raycast", action="store_true", help="skip VTK's (slow) ray caster")
    ap.add_argument("--rounds", type=int, default=2, help="repeat each measurement, keep the fastest")
    ap.add_argument("--json", help="also write the results here")
    ap.add_argument("--torus", type=float, metavar="MAXVOL",
                    help="also time a TetGen torus meshed with this maximum tet volume (0.00006: ~200k tets)")
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory(prefix="tetkit-bench-") as tmp:
        meshes = [("grid", t) for t in args.tets] + ([("torus", args.torus)] if args.torus else [])
        for kind, target in meshes:
            path = os.path.join(tmp, f"{kind}_{target}.vtk")
            if kind == "grid":
                ug = make_mesh(target, path)
                diag = 3 ** 0.5
            else:
                ug, diag = make_torus(target, tmp, args.tetkit, path)
            ntets = ug.GetNumberOfCells()
            # A fifth of the bounding-box diagonal, tetkit's default.
            ud = diag / 5.0
            row = {"mesh": kind, "tets": ntets, "vtk_version": vtk.vtkVersion.GetVTKVersion(), "load_before": os.getloadavg()[0]}
            png = os.path.join(tmp, "out.png")
            runs = {
                "vtk_pt": lambda: vtk_time(ug, "pt", args.frames, args.size, ud),
                "tetkit_kd_pre": lambda: tetkit_time(
                    args.tetkit, path, png, args.frames, args.size, ud, ["--sort", "kd", "--integration", "preintegrated"]),
                "tetkit_centroid_avg": lambda: tetkit_time(
                    args.tetkit, path, png, args.frames, args.size, ud, ["--sort", "centroid", "--integration", "average"]),
                "tetkit_raycast": lambda: tetkit_time(
                    args.tetkit, path, png, max(1, args.frames - 1), args.size, ud, ["--method", "raycast"]),
                "tetkit_raycast_table": lambda: tetkit_time(
                    args.tetkit, path, png, max(1, args.frames - 1), args.size, ud,
                    ["--method", "raycast", "--ray-integration", "preintegrated"]),
            }
            if not args.no_vtk_raycast:
                runs["vtk_raycast"] = lambda: vtk_time(ug, "raycast", max(1, args.frames - 1), args.size, ud)
            for _ in range(max(1, args.rounds)):
                for name, run in runs.items():
                    first, per_frame, cov = run()
                    if per_frame < row.get(name, float("inf")):
                        key = "first" if name.startswith("vtk") else "setup"
                        row[name], row[f"{name}_{key}"], row[f"{name}_coverage"] = per_frame, first, cov
            row["load_after"] = os.getloadavg()[0]
            rows.append(row)
            print(json.dumps(row), flush=True)
    print()
    print(f"load average (1 min) before/after each size: {[(r['load_before'], r['load_after']) for r in rows]}")
    print(f"coverage (share of non-black pixels), VTK PT / tetkit kd+pre: {[(round(r['vtk_pt_coverage'], 3), round(r['tetkit_kd_pre_coverage'], 3)) for r in rows]}")
    print(f"| mesh | tets | VTK PT | VTK ray cast | tetkit kd+preintegrated | tetkit centroid+average | tetkit ray cast (exact) | tetkit ray cast (table) | exact PT speed-up vs VTK PT | ray cast speed-up vs VTK (exact, table) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for r in rows:
        vr = f"{r['vtk_raycast']:.3f} s" if "vtk_raycast" in r else "-"
        rr = (f"{r['vtk_raycast'] / r['tetkit_raycast']:.1f}x, {r['vtk_raycast'] / r['tetkit_raycast_table']:.1f}x"
              if "vtk_raycast" in r else "-")
        print(f"| {r['mesh']} | {r['tets']} | {r['vtk_pt']:.3f} s | {vr} | {r['tetkit_kd_pre']:.3f} s (setup {r['tetkit_kd_pre_setup']:.2f} s) | "
              f"{r['tetkit_centroid_avg']:.3f} s | {r['tetkit_raycast']:.3f} s (setup {r['tetkit_raycast_setup']:.2f} s) | "
              f"{r['tetkit_raycast_table']:.3f} s | "
              f"{r['vtk_pt'] / r['tetkit_kd_pre']:.1f}x | {rr} |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
