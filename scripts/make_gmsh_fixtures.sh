#!/usr/bin/env bash
# Writes fixtures/gmsh/ with Gmsh (Debian package `gmsh`, 4.8): three solids meshed with tets, saved
# as Gmsh writes legacy VTK (version 2.0, ASCII, every element: tets plus the boundary triangles,
# feature lines and corner vertices). Real-world input for the readers and for --tetrahedralize
# (which keeps or drops the lower-dimensional cells).
#   block_hole.vtk  a 2 x 1 x 1 block with a cylindrical through-hole (non-convex, ~2k tets)
#   lshape.vtk      an L-shaped part (~1.4k tets)
#   cavity.vtk      a unit cube with an internal spherical cavity (two boundary shells, ~1.1k tets)
#   extruded.vtk    a plate with a hole, meshed with quads and triangles and extruded in 3 layers:
#                   hexahedra and wedges (Gmsh's structured extrusion), with boundary quads/triangles
#   hexgrid.vtk     a unit cube as a transfinite 5 x 5 x 5 grid of hexahedra (coordinates carry
#                   Gmsh's rounding, 0.4000000000000002): the default camera's eye lies on the
#                   grid's symmetry planes, where pixel rays graze edges
set -euo pipefail
out="$(cd "$(dirname "$0")/.." && pwd)/fixtures/gmsh"
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cat >"$work/block_hole.geo" <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 2, 1, 1};
Cylinder(2) = {0.7, 0.5, -0.1, 0, 0, 1.2, 0.3};
BooleanDifference{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Mesh.CharacteristicLengthMax = 0.18;
GEO
cat >"$work/lshape.geo" <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 2, 1, 0.6};
Box(2) = {0, 1, 0, 1, 1, 0.6};
BooleanUnion{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Mesh.CharacteristicLengthMax = 0.22;
GEO
cat >"$work/cavity.geo" <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Sphere(2) = {0.5, 0.5, 0.5, 0.25};
BooleanDifference{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Mesh.CharacteristicLengthMax = 0.17;
GEO
cat >"$work/extruded.geo" <<'GEO'
SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 2, 1};
Disk(2) = {0.6, 0.5, 0, 0.25};
BooleanDifference{ Surface{1}; Delete; }{ Surface{2}; Delete; }
Mesh.CharacteristicLengthMax = 0.2;
// Quads where the blossom recombination finds them, triangles elsewhere: hexes and wedges.
Mesh.RecombinationAlgorithm = 0;
Recombine Surface{1};
Extrude {0, 0, 0.3} { Surface{1}; Layers{3}; Recombine; }
GEO

cat >"$work/hexgrid.geo" <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Transfinite Curve{:} = 6;
Transfinite Surface{:};
Recombine Surface{:};
Transfinite Volume{:};
GEO

for name in block_hole lshape cavity extruded hexgrid; do
  gmsh -3 "$work/$name.geo" -format vtk -o "$work/$name.vtk" >"$work/$name.log" 2>&1 \
    || { cat "$work/$name.log"; exit 1; }
  # Gmsh names the file it wrote in the header; keep only the base name so the fixture does not
  # depend on where this script ran.
  sed "2s|.*|$name, Created by Gmsh|" "$work/$name.vtk" >"$out/$name.vtk"
  echo "$out/$name.vtk: $(wc -c <"$out/$name.vtk") bytes"
done
