#!/usr/bin/env bash
# Regenerates fixtures/tetgen/ with the Debian `tetgen` binary (TetGen 1.6) from closed surfaces
# that scripts/tetgen_surfaces.py writes as .poly files:
#   sphere.1.{node,ele,face,neigh}  icosphere (2 subdivisions), quality mesh, 1-based, with .neigh
#   torus.1.{node,ele,face}         non-convex torus (R=1, r=0.4), 0-based (-z)
#   quadratic.1.{node,ele,face}     two stacked unit cubes, 10-node tets (-o2)
#   regions.1.{node,ele,face}       the same two cubes as two regions, region attributes (-A)
#   cloud.1.{node,ele,face}         Delaunay tetrahedralization of 400 seeded random points with a
#                                   random attribute, no quality switch: slivers and long hull
#                                   tets (the pre-integration table's hard case, tests/render.rs)
# tetgen's own summary of each run goes to fixtures/tetgen/*.log, which the tests compare with.
set -euo pipefail
cd "$(dirname "$0")/.."
out=fixtures/tetgen
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 scripts/tetgen_surfaces.py "$tmp"
run() { # name switches
  local name=$1 switches=$2
  (cd "$tmp" && tetgen "$switches" "$name.poly" >"$name.log")
  rm -f "$tmp/$name.1.edge"
  mkdir -p "$out"
  for f in "$tmp/$name".1.* ; do cp "$f" "$out/"; done
  # Keep the counts tetgen printed (not its timings, which change run to run).
  grep -E '^ +Mesh (points|tetrahedra|faces on facets)' "$tmp/$name.log" >"$out/$name.log"
}
rm -f "$out"/*.node "$out"/*.ele "$out"/*.face "$out"/*.neigh "$out"/*.log
run sphere -pq1.4a0.05n
run torus -pq1.2a0.02z
run quadratic -pqo2
run regions -pq1.4a0.05A
/usr/bin/python3 - "$tmp/cloud.node" <<'PY'
import random, sys
random.seed(11)
with open(sys.argv[1], "w") as f:
    f.write("# 400 random points in the unit cube, one attribute (scripts/make_tetgen_fixtures.sh)\n")
    f.write("400 3 1 0\n")
    for i in range(400):
        f.write("%d %.6f %.6f %.6f %.6f\n" % ((i + 1,) + tuple(random.random() for _ in range(4))))
PY
(cd "$tmp" && tetgen cloud.node >cloud.log)
rm -f "$tmp/cloud.1.edge"
for f in "$tmp"/cloud.1.* ; do cp "$f" "$out/"; done
grep -E '^ +Mesh (points|tetrahedra):' "$tmp/cloud.log" >"$out/cloud.log"
# The unit cube's corners with second-order output and no other switch: TetGen writes 10-node
# tets but 3-node boundary faces (cube_o2.1.*).
printf '8 3 0 0\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n' >"$tmp/cube_o2.node"
(cd "$tmp" && tetgen -o2 cube_o2.node >cube_o2.log)
rm -f "$tmp/cube_o2.1.edge"
for f in "$tmp"/cube_o2.1.* ; do cp "$f" "$out/"; done
grep -E '^ +Mesh (points|tetrahedra):' "$tmp/cube_o2.log" >"$out/cube_o2.log"
ls -l "$out"
