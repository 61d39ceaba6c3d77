#!/usr/bin/env bash
# Writes fixtures/msh/ with Gmsh (Debian package `gmsh`, 4.8): small meshes saved as .msh in the
# versions and encodings tetkit reads, and the same meshes as Gmsh's own legacy VTK export in
# fixtures/msh/gmsh_vtk/ for comparison (tests/msh_fixtures.rs).
#   block_hole_41.msh, block_hole_41_bin.msh, block_hole_22.msh, block_hole_22_bin.msh
#               a 2 x 1 x 1 block with a cylindrical hole, tets, physical groups "solid" (volume),
#               "hole" and "outside" (surfaces): MSH 4.1 and 2.2, ASCII and binary
#   mixed_41.msh          a quarter ring swept from a quad-dominant face: hexahedra, prisms (the
#                         triangles) and pyramids (where a triangle touches the axis)
#   params_41.msh, params_41_bin.msh, params_22.msh
#                         mixed_41 with parametric coordinates (Mesh.SaveParametric): u on
#                         curves, u and v on surfaces (MSH 2.2: a $ParametricNodes section)
#   mixed_o2_41.msh       the same at order 2 (27-node hexahedra, 18-node prisms, 14-node pyramids)
#   mixed_o2i_22_bin.msh  order 2 incomplete (20-node hexahedra, 15-node prisms, 13-node
#                         pyramids), MSH 2.2 binary
#   tet_o2_41_bin.msh     a cube of 10-node tets, MSH 4.1 binary
#   views_41.msh          a coarse cube with data views: Gmsh's own $NodeData (Plugin(NewView),
#                         a constant) and $ElementNodeData (Plugin(MathEval), list based), plus
#                         hand-made sections this script appends: a second time step of the node
#                         view and an $ElementData vector view
#   twobodies_41.msh, twobodies_part_41.msh, twobodies_part_41_bin.msh, twobodies_part_22.msh
#                         a cube and a ball (physical volumes "box" 1 and "ball" 2, the cube's
#                         top face physical surface "boxtop" 3), unpartitioned and split by
#                         `-part 2` (MSH 4.1 ASCII and binary: $PartitionedEntities, whose
#                         interface surface gets its own triangles; MSH 2.2 ASCII: the
#                         partitions in each element's tags)
#   multi_group_22.msh    two unit cubes, the first in physical volumes "A" and "B", the second
#                         in "B": MSH 2.2 writes the first cube's tets once per group
set -euo pipefail
out="$(cd "$(dirname "$0")/.." && pwd)/fixtures/msh"
mkdir -p "$out/gmsh_vtk"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cat >"$work/block_hole.geo" <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 2, 1, 1};
Cylinder(2) = {0.7, 0.5, -0.1, 0, 0, 1.2, 0.3};
BooleanDifference{ Volume{1}; Delete; }{ Volume{2}; Delete; }
// Without a minimum Gmsh 4.8 refines far below the maximum; these fixtures stay small.
Mesh.MeshSizeMin = 0.45;
Mesh.MeshSizeMax = 0.5;
Physical Volume("solid") = {1};
// The hole's wall is the surface whose bounding box is the cylinder's.
hole() = Surface In BoundingBox{0.39, 0.19, -0.01, 1.01, 0.81, 1.01};
Physical Surface("hole") = {hole()};
all() = Surface{:};
Physical Surface("outside") = {all()};
Physical Surface("outside") -= {hole()};
GEO

cat >"$work/mixed.geo" <<'GEO'
Point(1) = {0, 0, 0, 0.5}; Point(2) = {1, 0, 0, 0.5}; Point(3) = {1, 0, 1, 0.5};
Point(4) = {0, 0, 1, 0.5};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Mesh.RecombinationAlgorithm = 0;
Recombine Surface{1};
// Swept about the z axis, on which one side lies: elements there collapse into prisms and
// pyramids.
Extrude {{0, 0, 1}, {0, 0, 0}, Pi/2} { Surface{1}; Layers{3}; Recombine; }
Physical Volume("ring") = {1};
GEO

cat >"$work/tet_o2.geo" <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Mesh.MeshSizeMin = 0.5;
Mesh.MeshSizeMax = 0.6;
Mesh.ElementOrder = 2;
Physical Volume("cube") = {1};
GEO

cat >"$work/views.geo" <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Mesh.MeshSizeMin = 0.5;
Mesh.MeshSizeMax = 0.7;
Physical Volume("cube") = {1};
Mesh 3;
Plugin(NewView).NumComp = 1;
Plugin(NewView).Value = 2.5;
Plugin(NewView).Run;
View[0].Name = "level";
Plugin(MathEval).Expression0 = "x + 2*y";
Plugin(MathEval).View = 0;
Plugin(MathEval).Run;
View[1].Name = "slope";
PostProcessing.SaveMesh = 1;
Save View[0] "views_node.msh";
PostProcessing.SaveMesh = 0;
Save View[1] "views_elementnode.msh";
GEO

cat >"$work/twobodies.geo" <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Sphere(2) = {3, 0.5, 0.5, 0.6};
Mesh.CharacteristicLengthMax = 0.5;
Physical Volume("box") = {1};
Physical Volume("ball") = {2};
Physical Surface("boxtop") = {6};
GEO

run() { # geo, output, extra gmsh options...
  local geo=$1 o=$2
  shift 2
  gmsh -3 "$work/$geo.geo" "$@" -o "$work/$o" >"$work/$o.log" 2>&1 || { cat "$work/$o.log"; exit 1; }
}
# Gmsh names the file it wrote in a VTK header; keep only the base name.
vtk() { sed "2s|.*|$2, Created by Gmsh|" "$work/$1" >"$out/gmsh_vtk/$2.vtk"; }

run block_hole block_hole_41.msh -format msh41
run block_hole block_hole_41_bin.msh -format msh41 -bin
run block_hole block_hole_22.msh -format msh22
run block_hole block_hole_22_bin.msh -format msh22 -bin
run block_hole block_hole.vtk -format vtk
vtk block_hole.vtk block_hole
run mixed mixed_41.msh -format msh41
run mixed mixed.vtk -format vtk
run mixed params_41.msh -format msh41 -setnumber Mesh.SaveParametric 1
run mixed params_41_bin.msh -format msh41 -bin -setnumber Mesh.SaveParametric 1
run mixed params_22.msh -format msh22 -setnumber Mesh.SaveParametric 1
vtk mixed.vtk mixed
run mixed mixed_o2_41.msh -format msh41 -order 2
run mixed mixed_o2.vtk -format vtk -order 2
vtk mixed_o2.vtk mixed_o2
run mixed mixed_o2i_22_bin.msh -format msh22 -bin -order 2 -setnumber Mesh.SecondOrderIncomplete 1
run mixed mixed_o2i.vtk -format vtk -order 2 -setnumber Mesh.SecondOrderIncomplete 1
vtk mixed_o2i.vtk mixed_o2i
run tet_o2 tet_o2_41_bin.msh -format msh41 -bin
run tet_o2 tet_o2.vtk -format vtk
vtk tet_o2.vtk tet_o2
run twobodies twobodies_41.msh -format msh41
run twobodies twobodies_part_41.msh -format msh41 -part 2
run twobodies twobodies_part_41_bin.msh -format msh41 -bin -part 2
run twobodies twobodies_part_22.msh -format msh22 -part 2
cat >"$work/multi.geo" <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Box(2) = {1, 0, 0, 1, 1, 1};
BooleanFragments{ Volume{1, 2}; Delete; }{}
Mesh.MeshSizeMin = 0.9;
Mesh.MeshSizeMax = 1.0;
Physical Volume("A", 1) = {1};
Physical Volume("B", 2) = {1, 2};
GEO
run multi multi_group_22.msh -format msh22
for f in block_hole_41 block_hole_41_bin block_hole_22 block_hole_22_bin mixed_41 params_41 \
  params_41_bin params_22 mixed_o2_41 mixed_o2i_22_bin tet_o2_41_bin twobodies_41 twobodies_part_41 \
  twobodies_part_41_bin twobodies_part_22 multi_group_22; do
  cp "$work/$f.msh" "$out/$f.msh"
done

(cd "$work" && gmsh -0 views.geo -format msh41 -o views_mesh.msh >views.log 2>&1) \
  || { cat "$work/views.log"; exit 1; }
# Gmsh's node view (mesh included), its element-node view's section, then the hand-made ones:
# step 1 of "level" (x - z at each node, time 0.5) and "velocity" (3 components) on the first
# three tetrahedra listed in $ElementData.
/usr/bin/python3 - "$work" "$out/views_41.msh" <<'PY'
import re, sys
work, dest = sys.argv[1], sys.argv[2]
mesh = open(work + "/views_node.msh").read()
elnode = open(work + "/views_elementnode.msh").read()
section = re.search(r"\$ElementNodeData\n.*?\$EndElementNodeData\n", elnode, re.S).group(0)
lines = mesh.split("\n")
i = lines.index("$Nodes")
nblocks, nnodes = (int(x) for x in lines[i + 1].split()[:2])
k, nodes = i + 2, []
for _ in range(nblocks):
    dim, tag, param, n = (int(x) for x in lines[k].split())
    tags = [int(t) for t in lines[k + 1:k + 1 + n]]
    xyz = [[float(v) for v in l.split()[:3]] for l in lines[k + 1 + n:k + 1 + 2 * n]]
    nodes += list(zip(tags, xyz))
    k += 1 + 2 * n
i = lines.index("$Elements")
nblocks = int(lines[i + 1].split()[0])
k, tets = i + 2, []
for _ in range(nblocks):
    dim, tag, etype, n = (int(x) for x in lines[k].split())
    if etype == 4:
        tets += [int(l.split()[0]) for l in lines[k + 1:k + 1 + n]]
    k += 1 + n
step = ['$NodeData', '1', '"level"', '1', '0.5', '3', '1', '1', str(len(nodes))]
step += ["%d %.17g" % (t, p[0] - p[2]) for t, p in nodes]
step += ['$EndNodeData']
el = ['$ElementData', '1', '"velocity"', '1', '0', '3', '0', '3', '3']
el += ["%d %d %d %d" % (t, j, 2 * j, -j) for j, t in enumerate(tets[:3])]
el += ['$EndElementData']
open(dest, "w").write(mesh + section + "\n".join(step + el) + "\n")
PY

cat "$out"/*.msh "$out"/gmsh_vtk/*.vtk | wc -c | sed "s|$| bytes in all|"
ls -l "$out" "$out/gmsh_vtk"
