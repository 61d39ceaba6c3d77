#!/usr/bin/python3
"""Writes the closed surfaces scripts/make_tetgen_fixtures.sh meshes with tetgen, as .poly files
in the directory given: an icosphere, a torus, and two stacked cubes (with region points)."""
import math
import sys


def icosphere(sub):
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
         (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    v = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in v]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(sub):
        cache = {}
        nf = []

        def mid(a, b):
            k = (min(a, b), max(a, b))
            if k not in cache:
                p = [(v[a][i] + v[b][i]) / 2 for i in range(3)]
                n = math.sqrt(sum(x * x for x in p))
                v.append(tuple(x / n for x in p))
                cache[k] = len(v) - 1
            return cache[k]

        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    return v, [(3, fa) for fa in f]


def torus(R, r, nu, nv):
    v, f = [], []
    for i in range(nu):
        for j in range(nv):
            u, w = 2 * math.pi * i / nu, 2 * math.pi * j / nv
            v.append(((R + r * math.cos(w)) * math.cos(u), (R + r * math.cos(w)) * math.sin(u),
                      r * math.sin(w)))
    for i in range(nu):
        for j in range(nv):
            a, b = i * nv + j, ((i + 1) % nu) * nv + j
            c, d = ((i + 1) % nu) * nv + (j + 1) % nv, i * nv + (j + 1) % nv
            f += [(3, (a, b, c)), (3, (a, c, d))]
    return v, f


def two_cubes():
    v = [(x, y, z) for z in (0, 1, 2) for (x, y) in ((0, 0), (1, 0), (1, 1), (0, 1))]
    quads = [(0, 1, 2, 3), (8, 9, 10, 11), (4, 5, 6, 7)]
    for lo in (0, 4):
        for k in range(4):
            a, b = lo + k, lo + (k + 1) % 4
            quads.append((a, b, b + 4, a + 4))
    return v, [(4, q) for q in quads]


def poly(path, v, f, regions=(), markers=None):
    with open(path, "w") as o:
        o.write(f"# {path.split('/')[-1]}: closed surface for tetgen (scripts/tetgen_surfaces.py)\n")
        o.write(f"{len(v)} 3 0 0\n")
        for i, p in enumerate(v):
            o.write(f"{i}\t{p[0]:.17g} {p[1]:.17g} {p[2]:.17g}\n")
        o.write(f"{len(f)} 1\n")
        for k, (n, ids) in enumerate(f):
            m = markers[k] if markers else 1
            o.write(f"1 0 {m}\n{n} {' '.join(map(str, ids))}\n")
        o.write("0\n")
        o.write(f"{len(regions)}\n")
        for k, (p, a) in enumerate(regions):
            o.write(f"{k + 1} {p[0]} {p[1]} {p[2]} {a} 0\n")


d = sys.argv[1]
poly(f"{d}/sphere.poly", *icosphere(2))
poly(f"{d}/torus.poly", *torus(1.0, 0.4, 24, 12))
v, f = two_cubes()
marks = [1, 2, 3] + [4] * 8
poly(f"{d}/quadratic.poly", v, f, markers=marks)
poly(f"{d}/regions.poly", v, f, regions=[((0.5, 0.5, 0.5), 1), ((0.5, 0.5, 1.5), 2)], markers=marks)
