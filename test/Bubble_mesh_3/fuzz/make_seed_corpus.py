#!/usr/bin/env python3
"""Writes the seed corpus of the fuzz harnesses into corpus/<target>/.

Run once to (re)create the committed seeds: python3 make_seed_corpus.py
Small valid files of every format plus typical broken ones. The surface
harness takes its extension from the first byte (0 off, 1 obj, 2 stl,
3 ply); the sol harness its expected vertex count (0 = any).
"""
import os
import random
import shutil
import struct

here = os.path.dirname(os.path.abspath(__file__))
corpus = os.path.join(here, "corpus")

TET_V = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TET_F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
CUBE_V = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
CUBE_F = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4),
          (2, 6, 3), (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]


def write(target, name, data):
    d = os.path.join(corpus, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def off(v, f, header="OFF"):
    s = "%s\n%d %d 0\n" % (header, len(v), len(f))
    s += "".join("%r %r %r\n" % p for p in v)
    s += "".join("%d %s\n" % (len(t), " ".join(map(str, t))) for t in f)
    return s


def obj(v, f):
    return "".join("v %r %r %r\n" % p for p in v) + "".join(
        "f %s\n" % " ".join(str(i + 1) for i in t) for t in f)


def normal(v, t):
    a, b, c = (v[i] for i in t)
    u = [b[k] - a[k] for k in range(3)]
    w = [c[k] - a[k] for k in range(3)]
    return (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])


def stl_ascii(v, f):
    s = "solid seed\n"
    for t in f:
        s += " facet normal %r %r %r\n  outer loop\n" % normal(v, t)
        s += "".join("   vertex %r %r %r\n" % v[i] for i in t)
        s += "  endloop\n endfacet\n"
    return s + "endsolid seed\n"


def stl_binary(v, f, count=None):
    b = b"binary seed".ljust(80, b" ") + struct.pack("<I", len(f) if count is None else count)
    for t in f:
        b += struct.pack("<3f", *normal(v, t))
        for i in t:
            b += struct.pack("<3f", *v[i])
        b += b"\0\0"
    return b


def ply_ascii(v, f, extra=False):
    s = "ply\nformat ascii 1.0\ncomment seed\nelement vertex %d\n" % len(v)
    s += "property float x\nproperty float y\nproperty float z\n"
    if extra:
        s += "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    s += "element face %d\nproperty list uchar int vertex_indices\nend_header\n" % len(f)
    s += "".join("%r %r %r%s\n" % (p + (" 255 0 0" if extra else "",)) for p in v)
    return s + "".join("3 %d %d %d\n" % t for t in f)


def ply_binary(v, f):
    s = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty double x\nproperty double y\n"
         "property double z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n" % (len(v), len(f)))
    b = s.encode()
    for p in v:
        b += struct.pack("<3d", *p)
    for t in f:
        b += struct.pack("<B3i", 3, *t)
    return b


def surface(name, kind, data):
    prefix = {"off": 0, "obj": 1, "stl": 2, "ply": 3}[kind]
    write("surface", name, bytes([prefix]) + (data if isinstance(data, bytes) else data.encode()))


def main():
    if os.path.isdir(corpus):
        for t in ("surface", "medit", "sol", "predicates"):
            shutil.rmtree(os.path.join(corpus, t), ignore_errors=True)
    # --- surfaces: valid
    surface("tet.off", "off", off(TET_V, TET_F))
    surface("cube.off", "off", off(CUBE_V, CUBE_F))
    surface("cube_coff_comments.off", "off",
            "COFF\n# colours and a comment\n8 12 0\n" + "".join("%d %d %d 1 0 0 1\n" % p for p in CUBE_V) +
            "".join("3 %d %d %d\n" % t for t in CUBE_F))
    surface("cube_flipped_face.off", "off", off(CUBE_V, [CUBE_F[0][::-1]] + CUBE_F[1:]))
    surface("tet.obj", "obj", obj(TET_V, TET_F))
    surface("cube_slashes.obj", "obj", "# seed\no cube\n" + "".join("v %d %d %d\n" % p for p in CUBE_V) +
            "vn 0 0 1\nvt 0 0\n" + "".join("f %d/1/1 %d/1/1 %d/1/1\n" % tuple(i + 1 for i in t) for t in CUBE_F))
    surface("tet_negative_indices.obj", "obj", "".join("v %d %d %d\n" % p for p in TET_V) +
            "".join("f %d %d %d\n" % tuple(i - 4 for i in t) for t in TET_F))
    surface("tet_ascii.stl", "stl", stl_ascii(TET_V, TET_F))
    surface("cube_binary.stl", "stl", stl_binary(CUBE_V, CUBE_F))
    surface("tet.ply", "ply", ply_ascii(TET_V, TET_F))
    surface("tet_colours.ply", "ply", ply_ascii(TET_V, TET_F, extra=True))
    surface("cube_binary.ply", "ply", ply_binary(CUBE_V, CUBE_F))
    # OFF variants and a big-endian PLY with extra properties and elements
    surface("tet_noff.off", "off", "NOFF\n4 4 0\n" + "".join("%d %d %d 0 0 1\n" % p for p in TET_V) +
            "".join("3 %d %d %d\n" % t for t in TET_F))
    surface("tet_cnoff_face_colours.off", "off",
            "CNOFF\n4 4 0\n" + "".join("%d %d %d 0 0 1 0.5 0.5 0.5 1\n" % p for p in TET_V) +
            "".join("3 %d %d %d 255 0 0\n" % t for t in TET_F))
    surface("tet_4off.off", "off", "4OFF\n4 4 0\n" + "".join("%d %d %d 2\n" % tuple(2 * c for c in p) for p in TET_V) +
            "".join("3 %d %d %d\n" % t for t in TET_F))
    surface("tet_stoff.off", "off", "STOFF 4 4 0\n" + "".join("%d %d %d 0.5 0.5\n" % p for p in TET_V) +
            "".join("3 %d %d %d\n" % t for t in TET_F))
    hb = ("ply\nformat binary_big_endian 1.0\ncomment seed\nobj_info x\nelement material 1\nproperty uchar r\n"
          "element vertex %d\nproperty float x\nproperty short y\nproperty double z\nproperty list uchar int8 n\n"
          "element face %d\nproperty int8 tag\nproperty list uint8 uint32 vertex_index\nend_header\n"
          % (len(CUBE_V), len(CUBE_F))).encode() + b"\x07"
    for p in CUBE_V:
        hb += struct.pack(">fhdBb", p[0], p[1], p[2], 1, -1)
    for t in CUBE_F:
        hb += struct.pack(">bB3I", 0, 3, *t)
    surface("cube_big_endian.ply", "ply", hb)
    # --- surfaces: broken
    surface("open.off", "off", off(TET_V, TET_F[:3]))
    surface("quad.off", "off", off(CUBE_V, [(0, 2, 3, 1)] + CUBE_F[2:]))
    surface("pinched.off", "off", off(TET_V + [(0, 0, -1), (1, 0, -1), (0, 1, -1)],
                                      TET_F + [(0, 4, 5), (0, 6, 4), (0, 5, 6), (4, 6, 5)]))
    surface("three_faces_on_edge.off", "off",
            off(TET_V + [(1, 1, 1)], TET_F + [(0, 1, 4), (1, 2, 4), (0, 4, 2)]))
    surface("nan.off", "off", off([(float("nan"), 0, 0)] + TET_V[1:], TET_F).replace("nan", "nan"))
    surface("index_out_of_range.off", "off", off(TET_V, TET_F[:3] + [(1, 2, 9)]))
    surface("degenerate_face.off", "off", off(TET_V, TET_F[:3] + [(1, 1, 3)]))
    surface("truncated.off", "off", off(CUBE_V, CUBE_F)[:60])
    # the classes that crashed, hung or exhausted memory in CGAL 5.5's readers
    surface("huge_counts.off", "off", "OFF\n2000000000 2000000000 0\n0 0 0\n")
    surface("colour_token.off", "off", off(TET_V, TET_F, "COFF").replace("0 0 0\n", "0 0 0 abc\n", 1))
    surface("property_first.ply", "ply", "ply\nformat ascii 1.0\nproperty float x\nelement vertex 1\nend_header\n0\n")
    surface("truncated_header.ply", "ply", ply_binary(CUBE_V, CUBE_F)[:70])
    surface("huge_count_binary.stl", "stl", stl_binary(TET_V, TET_F, count=0x7fffffff))
    surface("truncated_binary.ply", "ply", ply_binary(CUBE_V, CUBE_F)[:-30])
    surface("empty.obj", "obj", "# nothing\n")
    # --- MEDIT .mesh
    data = os.path.join(here, "..", "data")
    for name in ("cube6.mesh", "io_all_sections.mesh"):
        with open(os.path.join(data, name), "rb") as f:
            write("medit", name, f.read())
    with open(os.path.join(data, "cube6.mesh")) as f:
        cube6 = f.read()
    write("medit", "tet_corners_edges.mesh",
          "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 1\n1 0 0 1\n0 1 0 1\n0 0 1 1\n"
          "Edges\n1\n1 2 3\nTriangles\n1\n1 2 3 4\nTetrahedra\n1\n1 2 3 4 7\nCorners\n2\n1 4\nEnd\n")
    write("medit", "truncated.mesh", cube6[:150])
    write("medit", "index_out_of_range.mesh", cube6.replace("1 2 4 8 1", "1 2 4 9 1"))
    write("medit", "dimension2.mesh", cube6.replace("Dimension 3", "Dimension 2"))
    write("medit", "nan.mesh", cube6.replace("1 1 1 0", "nan 1 1 0"))
    write("medit", "huge_count.mesh", "MeshVersionFormatted 1\nDimension 3\nVertices\n2147483647\n0 0 0 0\n")
    # regression: "+-1" was read as -1 (fixed in medit.h's Token_reader)
    write("medit", "plus_minus_sign.mesh", cube6.replace("0 1 1 0", "0 +-1 1 0"))
    write("medit", "no_end_quads.mesh", cube6.replace("End\n", "Quadrilaterals\n1\n1 2 4 3 0\n"))
    # --- .sol (first byte: expected vertex count, 0 = any)
    ident = "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n8\n1 3\n" + "1 0 1 0 0 1\n" * 8 + "End\n"
    write("sol", "identity8.sol", bytes([8]) + ident.encode())
    write("sol", "identity_any.sol", bytes([0]) + ident.encode())
    write("sol", "count_mismatch.sol", bytes([7]) + ident.encode())
    write("sol", "not_spd.sol", bytes([0]) + ident.replace("1 0 1 0 0 1\n", "1 0 -1 0 0 1\n", 1).encode())
    write("sol", "scalar.sol", bytes([3]) + b"MeshVersionFormatted 1\nDimension 3\nSolAtVertices\n3\n1 1\n"
          b"0.5\n1e-3\n2\nEnd\n")
    write("sol", "anisotropic.sol", bytes([2]) + b"MeshVersionFormatted 2\nDimension 3\n# comment\n"
          b"SolAtTetrahedra 1 2 1 2 0.5 1 2 3\nSolAtVertices 2 1 3\n100 0.5 1 0.25 0.125 1e4\n"
          b"1e8 0 1 0 0 1e-3\nEnd\n")
    write("sol", "two_fields.sol", bytes([1]) + b"MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n1\n2 3 1\n"
          b"1 0 1 0 0 1 2\nEnd\n")
    write("sol", "truncated.sol", bytes([8]) + ident[:90].encode())
    write("sol", "nan.sol", bytes([1]) + b"MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n1\n1 3\n"
          b"nan 0 1 0 0 1\nEnd\n")
    # --- predicates: bytes are decoded by FuzzedDataProvider (integers from
    # the end), so random strings of a few lengths reach every mode.
    rng = random.Random(5)
    for i in range(40):
        write("predicates", "seed%02d" % i, bytes(rng.randrange(256) for _ in range(rng.choice((24, 48, 96, 160)))))


if __name__ == "__main__":
    main()
