#!/usr/bin/env python3
"""Writes blob.off: a smooth, star-shaped organic surface (a subdivided
icosahedron pushed out radially by a few low-frequency waves, stretched along
x), no sharp feature: the demo's organic model, meshed with a surface-aligned
boundary-layer metric."""
import math
import sys

LEVELS = 4


def icosphere(levels):
    t = (1 + math.sqrt(5)) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    v = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in v]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
         (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
         (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        mid = {}

        def m(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                p = [(v[a][k] + v[b][k]) / 2 for k in range(3)]
                n = math.sqrt(sum(x * x for x in p))
                mid[key] = len(v)
                v.append(tuple(x / n for x in p))
            return mid[key]
        nf = []
        for a, b, c in f:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    return v, f


def main(path):
    v, f = icosphere(LEVELS)
    out_v = []
    for x, y, z in v:
        r = 1 + 0.22 * math.sin(2.5 * x + 0.3) * math.cos(2 * y) + 0.15 * math.sin(3 * z + 0.5 * x)
        out_v.append((1.5 * r * x, r * y, r * z))
    vol = 0.0
    for a, b, c in f:
        p, q, r = out_v[a], out_v[b], out_v[c]
        vol += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0])
                + p[2] * (q[0] * r[1] - q[1] * r[0])) / 6
    if vol < 0:
        f = [(a, c, b) for a, b, c in f]
    with open(path, "w") as out:
        out.write("OFF\n%d %d 0\n" % (len(out_v), len(f)))
        for p in out_v:
            out.write("%.12g %.12g %.12g\n" % p)
        for t in f:
            out.write("3 %d %d %d\n" % t)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "blob.off")
