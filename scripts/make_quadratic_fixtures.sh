#!/usr/bin/env bash
# Writes fixtures/quadratic/ with Gmsh (Debian package `gmsh`, 4.8): meshes of second-order cells
# for tetrahedralization (tests/tetrahedralize.rs).
#   hex20_ring.msh  a quarter of a thick ring (r 1..2, 90 degrees, height 1) swept from a
#                   transfinite quad face: 8 x 2 x 2 hexahedra at order 2 incomplete (20 nodes,
#                   mid-edge nodes on the arcs, so the cells are curved), with the boundary's
#                   8-node quads, 3-node lines and corner points; MSH 4.1 ASCII
#   wedge15_ring.msh the same ring with the quad face left in triangles: 64 curved 15-node prisms
#                   on the same boundary nodes as hex20_ring.msh
#   box_o2_incomplete.msh, box_o2_complete.msh
#                   the box [0,2] x [0,1] x [0,1.5] with straight edges: 2 x 2 x 2 hexahedra on
#                   x < 1 and 16 prisms on x > 1 (both extruded in 2 layers from a quad and a
#                   triangle surface, so they share quad faces at x = 1), under a layer of tets
#                   that meets the hexahedra's tops with 4 pyramids; at order 2 incomplete (20-node
#                   hexahedra, 15-node prisms, 13-node pyramids, 10-node tets) and complete
#                   (27, 18, 14 and 10 nodes), with their boundary cells; MSH 4.1 ASCII
set -euo pipefail
out="$(cd "$(dirname "$0")/.." && pwd)/fixtures/quadratic"
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat >"$work/ring.geo" <<'GEO'
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Point(3) = {2, 0, 0};
Point(4) = {0, 2, 0};
Point(5) = {0, 1, 0};
Line(1) = {2, 3};
Circle(2) = {3, 1, 4};
Line(3) = {4, 5};
Circle(4) = {5, 1, 2};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = 3;
Transfinite Curve{2, 4} = 9;
Transfinite Surface{1};
Recombine Surface{1};
Extrude {0, 0, 1} { Surface{1}; Layers{2}; Recombine; }
GEO
gmsh -3 "$work/ring.geo" -format msh41 -order 2 -setnumber Mesh.SecondOrderIncomplete 1 \
  -o "$out/hex20_ring.msh" >"$work/log" 2>&1 || { cat "$work/log"; exit 1; }
sed '/^Recombine Surface/d' "$work/ring.geo" >"$work/ring_prisms.geo"
gmsh -3 "$work/ring_prisms.geo" -format msh41 -order 2 -setnumber Mesh.SecondOrderIncomplete 1 \
  -o "$out/wedge15_ring.msh" >"$work/log" 2>&1 || { cat "$work/log"; exit 1; }
cat >"$work/box.geo" <<'GEO'
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Point(3) = {2, 0, 0};
Point(4) = {2, 1, 0};
Point(5) = {1, 1, 0};
Point(6) = {0, 1, 0};
Line(1) = {1, 2};
Line(2) = {2, 5};
Line(3) = {5, 6};
Line(4) = {6, 1};
Line(5) = {2, 3};
Line(6) = {3, 4};
Line(7) = {4, 5};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, -2};
Plane Surface(2) = {2};
Transfinite Curve{1, 2, 3, 4, 5, 6, 7} = 3;
Transfinite Surface{1, 2};
Recombine Surface{1};
a[] = Extrude {0, 0, 1} { Surface{1}; Layers{2}; Recombine; };
b[] = Extrude {0, 0, 1} { Surface{2}; Layers{2}; Recombine; };
Extrude {0, 0, 0.5} { Surface{a[0], b[0]}; }
GEO
gmsh -3 "$work/box.geo" -format msh41 -order 2 -setnumber Mesh.SecondOrderIncomplete 1 \
  -o "$out/box_o2_incomplete.msh" >"$work/log" 2>&1 || { cat "$work/log"; exit 1; }
gmsh -3 "$work/box.geo" -format msh41 -order 2 \
  -o "$out/box_o2_complete.msh" >"$work/log" 2>&1 || { cat "$work/log"; exit 1; }
ls -l "$out"
