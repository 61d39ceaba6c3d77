#!/usr/bin/env bash
# Figures for the partition stage: makes a finer TetGen mesh (the torus of tetgen_surfaces.py) and a
# finer Gmsh mesh with a hole (the block of make_gmsh_fixtures.sh) in a temporary folder, then runs
# `cargo bench --bench partition`, which prints tet growth for 1, 2, 4, 8, 16 leaves with both plane
# searches on them and on regular/jittered structured grids, and times 1M tets into 8 leaves.
# Usage: scripts/partition_figures.sh [TORUS_MAX_VOLUME] [GMSH_SIZE]   (defaults 0.0004, 0.05)
set -euo pipefail
cd "$(dirname "$0")/.."
vol=${1:-0.0004}
size=${2:-0.05}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
/usr/bin/python3 scripts/tetgen_surfaces.py "$work" >/dev/null
(cd "$work" && tetgen "-pq1.2a${vol}z" torus.poly >torus.log)
cat >"$work/block_hole.geo" <<GEO
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 2, 1, 1};
Cylinder(2) = {0.7, 0.5, -0.1, 0, 0, 1.2, 0.3};
BooleanDifference{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Mesh.CharacteristicLengthMax = ${size};
GEO
gmsh -3 "$work/block_hole.geo" -format vtk -o "$work/block_hole.vtk" >"$work/gmsh.log" 2>&1
TETKIT_PARTITION_MESHES="$work/torus.1.ele:$work/block_hole.vtk" cargo bench --bench partition
