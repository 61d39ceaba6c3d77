#!/usr/bin/env bash
# Writes fixtures/medit/: ASCII Medit .mesh files from real tools, each beside the same mesh in
# another format from the same tool (for comparison), plus one hand-written file for the cell
# types no tool at hand writes.
#   tetgen_regions.mesh       TetGen 1.6 (`-pq1.4a0.1Ag`) on two stacked cubes with two region
#   tetgen_regions.node/.ele  attributes: MeshVersionFormatted 1, Triangles (all tet faces, refs =
#                             facet markers), Tetrahedra (refs = regions 1, 2), Corners, Edges
#                             (after Corners); the same run's .node/.ele hold the tets with the
#                             region attribute. (TetGen 1.6's own VTK output, `-k`, numbers points
#                             from 1, which no VTK reader accepts, so it is not kept.)
#   gmsh_tets.mesh/.vtk       Gmsh 4.8: two unit cubes side by side meshed with tets, physical
#                             volumes 10 and 20 and a physical surface 3 on every face, saved with
#                             Mesh.SaveElementTagType = 2 so the refs are the physical tags
#                             (vertex refs are Gmsh's entity tags). The .vtk also holds the boundary
#                             triangles, then the tets.
#   gmsh_hex.mesh/.vtk        Gmsh 4.8: a transfinite 3 x 3 x 3 grid of hexahedra (physical volume
#                             7, physical surfaces 1..6 on the faces): Quadrilaterals + Hexahedra.
#   hand_mixed.mesh           written here: a hexahedron with a prism on half its top face and a
#                             pyramid under its bottom face (prism in Gmsh's reference order,
#                             pyramid as Gmsh and VTK order it; see formats/src/medit/mod.rs), with
#                             Ridges and RequiredVertices. Gmsh 4.8 silently drops prisms and pyramids when it
#                             saves .mesh (checked: an extruded plate with 22 prisms comes out with
#                             its hexahedra only, and a hex/tet mesh loses its 24 pyramids), and
#                             TetGen writes tets only.
set -euo pipefail
cd "$(dirname "$0")/.."
out=fixtures/medit
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
rm -f "$out"/*.mesh "$out"/*.vtk "$out"/*.node "$out"/*.ele

/usr/bin/python3 scripts/tetgen_surfaces.py "$tmp"
(cd "$tmp" && tetgen -pq1.4a0.1Ag regions.poly >regions.log)
for ext in mesh node ele; do cp "$tmp/regions.1.$ext" "$out/tetgen_regions.$ext"; done

cat >"$tmp/tets.geo" <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Box(2) = {1, 0, 0, 1, 1, 1};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Physical Volume("left", 10) = {1};
Physical Volume("right", 20) = {2};
Physical Surface("skin", 3) = Surface{:};
Mesh.MeshSizeMin = 0.5;
Mesh.MeshSizeMax = 0.6;
Mesh.SaveElementTagType = 2;
GEO
cat >"$tmp/hex.geo" <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 2, 1};
Transfinite Curve{:} = 4;
Transfinite Surface{:};
Recombine Surface{:};
Transfinite Volume{:};
Physical Volume("block", 7) = {1};
For s In {1:6}
  Physical Surface(s) = {s};
EndFor
Mesh.SaveElementTagType = 2;
GEO
for name in tets hex; do
  for fmt in mesh vtk; do
    gmsh -3 "$tmp/$name.geo" -format $fmt -o "$tmp/$name.$fmt" >"$tmp/$name.$fmt.log" 2>&1 \
      || { cat "$tmp/$name.$fmt.log"; exit 1; }
  done
  cp "$tmp/$name.mesh" "$out/gmsh_$name.mesh"
  # Gmsh names the file it wrote in the header; keep only the base name.
  sed "2s|.*|gmsh_$name, Created by Gmsh|" "$tmp/$name.vtk" >"$out/gmsh_$name.vtk"
done

cat >"$out/hand_mixed.mesh" <<'MESH'
# A unit cube (hexahedron) with a prism on the front half of its top face and a pyramid under
# its bottom face, written by hand for tetkit's tests (scripts/make_medit_fixtures.sh).
MeshVersionFormatted 2

Dimension 3

Vertices
13
0 0 0 1
1 0 0 1
1 1 0 1
0 1 0 1
0 0 1 2
1 0 1 2
1 1 1 2
0 1 1 2
0 0 2 3
1 0 2 3
0.5 0.5 -1 4
0 0.5 1 0
0 0.5 2 3

Edges
2
1 2 5
2 3 5

Hexahedra
1
1 2 3 4 5 6 7 8 1

# (1 2 3) and (4 5 6) are the two triangles, k + 3 above k; (1 2 3) turns counter-clockwise
# seen from (4 5 6).
Prisms
1
5 6 12 9 10 13 2

# The base quad, whose right-hand normal points at the apex, then the apex.
Pyramids
1
1 4 3 2 11 3

RequiredVertices
2
1 11

Ridges
1
2

End
MESH
ls -l "$out"
