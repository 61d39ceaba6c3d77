#!/usr/bin/env bash
# Regenerates fixtures/sort/ with the Debian `tetgen` binary (TetGen 1.6):
#   pinwheel.1.{node,ele}  a conforming box mesh (0-based, -z) holding three long tets in a
#                          visibility cycle seen from +z (scripts/sort_pinwheel_poly.py); -Y keeps
#                          the facets unsplit so each of the three stays one tet (regions 1-3).
set -euo pipefail
cd "$(dirname "$0")/.."
out=fixtures/sort
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 scripts/sort_pinwheel_poly.py "$tmp"
(cd "$tmp" && tetgen -pYAz pinwheel.poly >pinwheel.log)
mkdir -p "$out"
rm -f "$out"/pinwheel.*
cp "$tmp/pinwheel.1.node" "$tmp/pinwheel.1.ele" "$out/"
grep -E '^ +Mesh (points|tetrahedra)' "$tmp/pinwheel.log" >"$out/pinwheel.log"
ls -l "$out"
