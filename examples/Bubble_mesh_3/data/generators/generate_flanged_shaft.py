#!/usr/bin/env python3
"""Writes flanged_shaft.off: a closed triangle surface of revolution about the
z axis (a flange of radius 1, a shaft of radius 0.55, a collar of radius 0.75;
height 2.6) with sharp circular edges: the demo's mechanical part, meshed with
a cylindrical anisotropy around its axis."""
import math
import sys

SEGMENTS = 96
# profile (r, z) from the bottom pole to the top pole
PROFILE = [(0.0, 0.0), (1.0, 0.0), (1.0, 0.4), (0.55, 0.4), (0.55, 2.2), (0.75, 2.2), (0.75, 2.6), (0.0, 2.6)]
MAX_STEP = 0.1


def subdivided(profile):
    out = [profile[0]]
    for (r0, z0), (r1, z1) in zip(profile, profile[1:]):
        n = max(1, math.ceil(math.hypot(r1 - r0, z1 - z0) / MAX_STEP))
        out += [(r0 + (r1 - r0) * k / n, z0 + (z1 - z0) * k / n) for k in range(1, n + 1)]
    return out


def main(path):
    prof = subdivided(PROFILE)
    verts, ids = [], []
    for r, z in prof:
        if r == 0.0:
            ids.append([len(verts)])
            verts.append((0.0, 0.0, z))
        else:
            ids.append([len(verts) + j for j in range(SEGMENTS)])
            verts += [(r * math.cos(2 * math.pi * j / SEGMENTS), r * math.sin(2 * math.pi * j / SEGMENTS), z)
                      for j in range(SEGMENTS)]
    faces = []
    for a, b in zip(ids, ids[1:]):
        for j in range(SEGMENTS):
            j1 = (j + 1) % SEGMENTS
            if len(a) == 1:
                faces.append((a[0], b[j1], b[j]))
            elif len(b) == 1:
                faces.append((a[j], a[j1], b[0]))
            else:
                faces.append((a[j], a[j1], b[j1]))
                faces.append((a[j], b[j1], b[j]))
    vol = 0.0
    for f in faces:
        p, q, r = (verts[i] for i in f)
        vol += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0])
                + p[2] * (q[0] * r[1] - q[1] * r[0])) / 6
    if vol < 0:
        faces = [(f[0], f[2], f[1]) for f in faces]
    with open(path, "w") as out:
        out.write("OFF\n%d %d 0\n" % (len(verts), len(faces)))
        for v in verts:
            out.write("%.12g %.12g %.12g\n" % v)
        for f in faces:
            out.write("3 %d %d %d\n" % f)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "flanged_shaft.off")
