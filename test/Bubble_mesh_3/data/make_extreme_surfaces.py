#!/usr/bin/env python3
"""Extreme but valid inputs for bubble_mesh_3 (issue 5, robustness).

    make_extreme_surfaces.py OUT_DIR

writes closed, outward-oriented triangle surfaces (ASCII OFF) into OUT_DIR:

  cube.off          unit cube [0,1]^3 (for the anisotropic metric cases)
  plate.off         thin plate 1 x 1 x 0.02
  plate_small.off   thin plate 0.25 x 0.25 x 0.02 (isotropic size across the thickness)
  needle.off        hexagonal needle, 0.02 across the flats, length 1 (along z)
  wedge10.off       triangular prism whose two long faces meet at a 10 degree
                    dihedral angle (apex edge along z, length 1 in x, height 0.3)
  cube_offset.off   unit cube translated by (1e6, 1e6, 1e6)
  cube_1e-6.off     cube of side 1e-6
  cube_1e6.off      cube of side 1e6
  cube_cylinder.off the UGAWG cube-cylinder: the unit cube minus the cylinder of
                    radius 0.5 about the z axis (the arc in 64 segments)

and a background mesh for a size grading of 1:1000 across the unit cube:

  graded_bg.mesh    Kuhn tet grid of [0,1]^3 (12^3 cells, MEDIT)
  graded_bg.sol     isotropic metrics, type 3 (m11 m21 m22 m31 m32 m33), of size
                    h = min(1, 1e-3 exp(K (x+y+z))), K = 30: 1e-3 at the corner
                    (0,0,0), 1 beyond x+y+z = ln(1000)/K ~ 0.23. log h is linear
                    there, so the log-Euclidean interpolation reproduces it exactly.
                    About 3,000 nodes.
  graded_bg_steep.sol the same with K = 60 (1e-3 to 1 within x+y+z < 0.12),
                    about 500 nodes (the quick CLI test).

Every surface is checked before it is written: each undirected edge is used by
exactly two faces, once in each direction (closed, manifold, consistently
oriented), and the signed volume is positive (outward) and equals the expected
one. Only the standard library is used.
"""
import math
import os
import sys


def box(x0, y0, z0, x1, y1, z1):
    v = [(x, y, z) for z in (z0, z1) for y in (y0, y1) for x in (x0, x1)]
    # vertex k = (k&1, (k>>1)&1, (k>>2)&1); faces outward
    f = [(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4),
         (2, 6, 7), (2, 7, 3), (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5)]
    return v, f


def prism(polygon, z0, z1, apex=0):
    """Right prism over a counter-clockwise polygon (x, y) that is star-shaped
    from its vertex `apex` (convex: any vertex); top and bottom are fans from it."""
    n = len(polygon)
    v = [(x, y, z0) for x, y in polygon] + [(x, y, z1) for x, y in polygon]
    f = []
    for k in range(1, n - 1):
        i, j = (apex + k) % n, (apex + k + 1) % n
        f.append((apex, j, i))              # bottom, facing -z
        f.append((n + apex, n + i, n + j))  # top, facing +z
    for i in range(n):
        j = (i + 1) % n
        f.append((i, j, n + j))
        f.append((i, n + j, n + i))
    return v, f


def signed_volume(v, f):
    s = 0.0
    for a, b, c in f:
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = v[a], v[b], v[c]
        s += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)
    return s / 6.0


def check_surface(name, v, f, expected_volume):
    directed = {}
    for a, b, c in f:
        if len({a, b, c}) != 3:
            raise SystemExit(f"{name}: degenerate face {a} {b} {c}")
        for e in ((a, b), (b, c), (c, a)):
            directed[e] = directed.get(e, 0) + 1
    for (a, b), k in directed.items():
        if k != 1:
            raise SystemExit(f"{name}: directed edge {a}-{b} used {k} times (inconsistent orientation "
                             "or non-manifold)")
        if directed.get((b, a), 0) != 1:
            raise SystemExit(f"{name}: edge {a}-{b} has no opposite half-edge (the surface is not closed)")
    # The volume is computed relative to the first vertex so that offset
    # surfaces do not lose digits.
    o = v[0]
    vol = signed_volume([(x - o[0], y - o[1], z - o[2]) for x, y, z in v], f)
    if not vol > 0:
        raise SystemExit(f"{name}: signed volume {vol} is not positive (the surface faces inward)")
    if abs(vol - expected_volume) > 1e-9 * expected_volume:
        raise SystemExit(f"{name}: volume {vol} differs from the expected {expected_volume}")


def write_off(path, comment, v, f):
    with open(path, "w") as out:
        out.write("OFF\n# %s\n%d %d 0\n" % (comment, len(v), len(f)))
        for p in v:
            out.write("%s %s %s\n" % tuple(repr(float(c)) for c in p))
        for a, b, c in f:
            out.write("3 %d %d %d\n" % (a, b, c))


def surfaces():
    s = []
    s.append(("cube.off", "unit cube", box(0, 0, 0, 1, 1, 1), 1.0))
    s.append(("plate.off", "thin plate 1 x 1 x 0.02", box(0, 0, 0, 1, 1, 0.02), 0.02))
    s.append(("plate_small.off", "thin plate 0.25 x 0.25 x 0.02", box(0, 0, 0, 0.25, 0.25, 0.02),
              0.25 * 0.25 * 0.02))
    r = 0.01 / math.cos(math.pi / 6)  # 0.02 across the flats
    hexagon = [(r * math.cos(k * math.pi / 3), r * math.sin(k * math.pi / 3)) for k in range(6)]
    s.append(("needle.off", "hexagonal needle, 0.02 across the flats, length 1",
              prism(hexagon, 0, 1), 1.5 * math.sqrt(3) * r * r))
    t = math.tan(math.radians(5))
    wedge = [(0, 0), (1, -t), (1, t)]
    s.append(("wedge10.off", "triangular prism with a 10 degree dihedral angle at the edge x=y=0",
              prism(wedge, 0, 0.3), 0.3 * t))
    off = 1e6
    s.append(("cube_offset.off", "unit cube translated by (1e6, 1e6, 1e6)",
              box(off, off, off, off + 1, off + 1, off + 1), 1.0))
    s.append(("cube_1e-6.off", "cube of side 1e-6", box(0, 0, 0, 1e-6, 1e-6, 1e-6), 1e-18))
    s.append(("cube_1e6.off", "cube of side 1e6", box(0, 0, 0, 1e6, 1e6, 1e6), 1e18))
    n = 64  # the quarter circle of radius 0.5, from (0, 0.5) down to (0.5, 0)
    arc = [(0.5 * math.sin(math.pi / 2 * k / n), 0.5 * math.cos(math.pi / 2 * k / n)) for k in range(n + 1)]
    arc[0], arc[n] = (0.0, 0.5), (0.5, 0.0)
    section = [(1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] + arc  # star-shaped from (1, 1)
    quarter_disk = 0.5 * 0.25 * n * math.sin(math.pi / 2 / n)
    s.append(("cube_cylinder.off", "UGAWG cube-cylinder: unit cube minus the cylinder r <= 0.5 about z",
              prism(section, 0, 1, apex=1), 1.0 - quarter_disk))
    return s


def graded_size(x, y, z, h0=1e-3, k=30.0, hmax=1.0):
    return min(hmax, h0 * math.exp(k * (x + y + z)))


def write_graded_sol(path, pts, k):
    with open(path, "w") as out:
        out.write("MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n%d\n1 3\n" % len(pts))
        for x, y, z in pts:
            m = 1.0 / graded_size(x, y, z, k=k) ** 2
            out.write("%.17g 0 %.17g 0 0 %.17g\n" % (m, m, m))
        out.write("End\n")


def write_graded_background(out_dir, n=12):
    idx = lambda i, j, k: 1 + i + (n + 1) * (j + (n + 1) * k)
    pts = [(i / n, j / n, k / n) for k in range(n + 1) for j in range(n + 1) for i in range(n + 1)]
    tets = []
    # Kuhn (Freudenthal) subdivision: one tet per path 0 -> (1,1,1) through the
    # unit steps of a permutation; conforming across cells. Odd permutations
    # are reversed so that every tet is positively oriented.
    perms = [((0, 1, 2), 1), ((1, 2, 0), 1), ((2, 0, 1), 1),
             ((1, 0, 2), -1), ((0, 2, 1), -1), ((2, 1, 0), -1)]
    for k in range(n):
        for j in range(n):
            for i in range(n):
                for perm, sign in perms:
                    c = [i, j, k]
                    path = [idx(*c)]
                    for axis in perm:
                        c[axis] += 1
                        path.append(idx(*c))
                    if sign < 0:
                        path[0], path[1] = path[1], path[0]
                    tets.append(path)
    with open(os.path.join(out_dir, "graded_bg.mesh"), "w") as out:
        out.write("MeshVersionFormatted 2\nDimension 3\nVertices\n%d\n" % len(pts))
        for p in pts:
            out.write("%r %r %r 0\n" % p)
        out.write("Tetrahedra\n%d\n" % len(tets))
        for t in tets:
            out.write("%d %d %d %d 1\n" % tuple(t))
        out.write("End\n")
    write_graded_sol(os.path.join(out_dir, "graded_bg.sol"), pts, 30.0)
    write_graded_sol(os.path.join(out_dir, "graded_bg_steep.sol"), pts, 60.0)


def main():
    # an option (-h, --help) is not an output folder: print the usage
    if len(sys.argv) != 2 or sys.argv[1].startswith("-"):
        raise SystemExit(__doc__)
    out_dir = sys.argv[1]
    os.makedirs(out_dir, exist_ok=True)
    for name, comment, (v, f), volume in surfaces():
        check_surface(name, v, f, volume)
        write_off(os.path.join(out_dir, name), comment, v, f)
    write_graded_background(out_dir)


if __name__ == "__main__":
    main()
