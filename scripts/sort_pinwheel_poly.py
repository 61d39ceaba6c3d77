#!/usr/bin/python3
"""Writes pinwheel.poly (into the directory given) for scripts/make_sort_fixtures.sh: three long
thin tets that lie over one another in a cycle seen from +z (each passes above the next where
their shadows cross), inside a box [-1.6, 1.6]^2 x [-0.5, 1.5]. The faces of the three tets are
facets, and each tet is its own region (1, 2, 3; the box's filler is region 10), so TetGen with
-pY keeps each one as a single tet of a conforming mesh."""
import math
import sys


def pinwheel():
    pts, tets = [], []
    for i in range(3):
        a = i * 2 * math.pi / 3
        dx, dy = math.cos(a), math.sin(a)
        nx, ny = -dy, dx
        # High (z = 1) at one end, a short vertical edge near z = 0 at the other, offset sideways
        # so that the three cross pairwise.
        c = (0.3 * nx, 0.3 * ny)
        b = len(pts)
        pts.append((c[0] - dx + 0.15 * nx, c[1] - dy + 0.15 * ny, 1.0))
        pts.append((c[0] - dx - 0.15 * nx, c[1] - dy - 0.15 * ny, 1.0))
        pts.append((c[0] + dx, c[1] + dy, 0.0))
        pts.append((c[0] + dx, c[1] + dy, 0.1))
        tets.append((b, b + 1, b + 2, b + 3))
    return pts, tets


def main(out):
    pts, tets = pinwheel()
    b0 = len(pts)
    pts += [(x, y, z) for z in (-0.5, 1.5) for (x, y) in ((-1.6, -1.6), (1.6, -1.6), (1.6, 1.6), (-1.6, 1.6))]
    facets = [[b0 + v for v in q] for q in [(0, 1, 2, 3), (4, 5, 6, 7)]]
    facets += [[b0 + k, b0 + (k + 1) % 4, b0 + (k + 1) % 4 + 4, b0 + k + 4] for k in range(4)]
    for t in tets:
        for skip in range(4):
            facets.append([t[j] for j in range(4) if j != skip])
    with open(f"{out}/pinwheel.poly", "w") as o:
        o.write(f"{len(pts)} 3 0 0\n")
        for i, p in enumerate(pts):
            o.write(f"{i} {p[0]!r} {p[1]!r} {p[2]!r}\n")
        o.write(f"{len(facets)} 0\n")
        for f in facets:
            o.write(f"1\n{len(f)} " + " ".join(map(str, f)) + "\n")
        o.write("0\n")
        o.write(f"{len(tets) + 1}\n")
        for i, t in enumerate(tets):
            c = [sum(pts[v][k] for v in t) / 4 for k in range(3)]
            o.write(f"{i} {c[0]!r} {c[1]!r} {c[2]!r} {i + 1} 0\n")
        o.write(f"{len(tets)} 1.5 1.5 1.4 10 0\n")


if __name__ == "__main__":
    main(sys.argv[1])
