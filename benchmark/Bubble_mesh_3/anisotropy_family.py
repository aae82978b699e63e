#!/usr/bin/env python3
"""Strong-anisotropy family (issue 18): the command-line tool on curved CGAL
surfaces x metrics given as MEDIT .sol on a TetGen background mesh, each run in
its own process, at a target vertex count.

    anisotropy_family.py --tool build/bin/bubble_mesh_3 --meshes DIR [options]

(scripts/anisotropy installs what it needs: numpy, scipy and Debian's tetgen
binary, builds the tool, fetches CGAL's data set and runs it.)

Metrics (sizes scaled so that the metric's node estimate is --vertices):
  cyl3      cylindrical: size h along and across the axis (the bounding box's
            longest axis through its centre), tangential size growing from h on
            the axis to 3h at the box's half width
  bl4, bl10 boundary layer on the whole (curved) wall: size h/R normal to the
            surface at the wall, growing linearly to h at depth 5h; tangential h
  shock10, shock40
            shock layer: a plane through the box centre, oblique to the axes so
            that it crosses the part's feature curves; thickness 1/20 of the
            diagonal with normal size h/R, growing outside by 0.3 per unit
            length to h; h along the plane
The normal of the wall is the direction to the closest point of the surface
(the closest face's normal on the wall): exact point-triangle distances. (The
version that wrote RESULTS_anisotropy.md searched only the faces of the 24
nearest centroids, which can miss large faces: on the background vertices of
knot1, blobby, elephant and fandisk it gave the same distances, to 4e-6 of the
diagonal. On the wall itself the normal is that of one nearest face, and at the
input's vertices and edges the faces tie: the two searches pick different ones,
so blobby's bl4 metric differs at 890 of 64,045 background vertices, by up to
35 %, and that run went from 400*/122 to 109/147 packing iterations.)

The background mesh: TetGen (`tetgen -pq1.4a<V/N>`, Debian's tetgen binary) of
the surface with about --background-tets tets; the metric is computed at its
vertices and written as SolAtVertices (type 3). The tool interpolates it
(log-Euclidean).

Table: exit, vertices, seconds per stage (packing, boundary front, advancing
front, improvement), packing iterations per stage (an 's' marks a stage that
settled, see Bubble_packer_3::Stage_statistics::settled; a '*' one stopped
at its cap), nodes the boundary front added, worst / p01 metric minimum
dihedral angle, worst metric mean ratio, metric edges in [1/sqrt2, sqrt2] after
the advancing front and after the improvement. Exit status 0 when every run
gave a mesh, no packing stage stopped at its iteration cap, and every run met
the floors of issue 18 (worst metric minimum dihedral and metric edges in
range: 10 deg and 90 % up to 1:10, 5 deg and 85 % for shock40); the runs that
did not are listed with the reason at the end (--no-floors: exits and caps
only).
"""
import argparse
import concurrent.futures
import json
import math
import os
import shutil
import subprocess
import sys
import time

import numpy as np
from scipy.spatial import cKDTree

CASES = ["cyl3", "bl4", "bl10", "shock10", "shock40"]
SURFACES = ["elephant.off", "knot1.off", "fandisk.off", "bunny00.off", "blobby.off"]


def read_off(path):
    with open(path, "r", errors="replace") as f:
        toks = [l.split("#", 1)[0].split() for l in f]
    toks = [t for t in toks if t]
    i = 0
    head = toks[0]
    if head[0].upper().endswith("OFF"):
        head = head[1:] or toks[1]
        i = 1 if toks[0][1:] else 2
    nv, nf = int(head[0]), int(head[1])
    P = np.array([[float(x) for x in toks[i + k][:3]] for k in range(nv)])
    i += nv
    F = []
    for k in range(nf):
        t = toks[i + k]
        n = int(t[0])
        idx = [int(x) for x in t[1:1 + n]]
        for j in range(1, n - 1):  # fan, for the rare polygon
            F.append([idx[0], idx[j], idx[j + 1]])
    return P, np.array(F, dtype=np.int64)


def closest_on_triangles(p, a, b, c):
    """Closest points to p on triangles (a, b, c), all arrays (n, 3): the
    Voronoi-region case analysis of the point-triangle distance."""
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = np.einsum("ij,ij->i", ab, ap), np.einsum("ij,ij->i", ac, ap)
    bp = p - b
    d3, d4 = np.einsum("ij,ij->i", ab, bp), np.einsum("ij,ij->i", ac, bp)
    cp = p - c
    d5, d6 = np.einsum("ij,ij->i", ab, cp), np.einsum("ij,ij->i", ac, cp)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        den = va + vb + vc
        v = np.where(den != 0, vb / den, 0.0)
        w = np.where(den != 0, vc / den, 0.0)
        res = a + ab * v[:, None] + ac * w[:, None]  # inside the face
        # edges
        t_ab = np.where(d1 - d3 != 0, d1 / (d1 - d3), 0.0)
        m = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
        res[m] = (a + ab * t_ab[:, None])[m]
        t_ac = np.where(d2 - d6 != 0, d2 / (d2 - d6), 0.0)
        m = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
        res[m] = (a + ac * t_ac[:, None])[m]
        t_bc = np.where((d4 - d3) + (d5 - d6) != 0, (d4 - d3) / ((d4 - d3) + (d5 - d6)), 0.0)
        m = (va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0)
        res[m] = (b + (c - b) * t_bc[:, None])[m]
    # vertices
    m = (d1 <= 0) & (d2 <= 0)
    res[m] = a[m]
    m = (d3 >= 0) & (d4 <= d3)
    res[m] = b[m]
    m = (d6 >= 0) & (d5 <= d6)
    res[m] = c[m]
    return res


def wall_distance_and_normal(X, P, F, candidates=24, chunk=20000):
    """Distance of each point of X to the surface (P, F) and the unit direction
    away from the wall (from the closest point to the point; the closest face's
    outward normal reversed on the wall itself). Exact: the faces whose
    centroids are nearest give an upper bound d of each point's distance; a face
    closer than d has its centroid within d + its radius (largest centroid to
    vertex distance). The faces are bucketed by radius (up to the median, the
    90th and 99th percentiles, the rest), each bucket searched within d + its
    largest radius, so that a few large faces (CAD-like inputs) do not widen
    the search for the many small ones. (Testing the large faces against every
    point instead took 20 minutes on the bunny's 265,000 background points.)"""
    A, B, C = P[F[:, 0]], P[F[:, 1]], P[F[:, 2]]
    N = np.cross(B - A, C - A)
    N /= np.maximum(np.linalg.norm(N, axis=1), 1e-300)[:, None]
    centroid = (A + B + C) / 3
    radius = np.max([np.linalg.norm(V - centroid, axis=1) for V in (A, B, C)], axis=0)
    best_d = np.full(len(X), np.inf)
    best_q = np.zeros_like(X)
    best_f = np.zeros(len(X), dtype=np.int64)

    def test(points, faces):
        q = closest_on_triangles(X[points], A[faces], B[faces], C[faces])
        d = np.linalg.norm(X[points] - q, axis=1)
        order = np.lexsort((d, points))  # per point, the nearest first
        points, d, q, faces = points[order], d[order], q[order], faces[order]
        first = np.ones(len(points), dtype=bool)
        first[1:] = points[1:] != points[:-1]
        points, d, q, faces = points[first], d[first], q[first], faces[first]
        m = d < best_d[points]
        best_d[points[m]], best_q[points[m]], best_f[points[m]] = d[m], q[m], faces[m]

    # an upper bound from the nearest centroids
    tree = cKDTree(centroid)
    k = min(candidates, len(F))
    for lo in range(0, len(X), chunk):
        idx = np.arange(lo, min(lo + chunk, len(X)))
        _, cand = tree.query(X[idx], k=k)
        cand = np.asarray(cand).reshape(len(idx), k)
        test(np.repeat(idx, k), cand.ravel())
    # every face that can be closer, bucket by bucket
    limits = np.unique(np.percentile(radius, [50, 90, 99, 100]))
    previous = -np.inf
    for r in limits:
        faces = np.nonzero((radius > previous) & (radius <= r))[0]
        previous = r
        if not len(faces):
            continue
        bucket = cKDTree(centroid[faces])
        for lo in range(0, len(X), chunk):
            idx = np.arange(lo, min(lo + chunk, len(X)))
            lists = bucket.query_ball_point(X[idx], best_d[idx] + r)
            counts = [len(l) for l in lists]
            if sum(counts):
                test(np.repeat(idx, counts), faces[np.concatenate([np.asarray(l, dtype=np.int64) for l in lists])])
    away = X - best_q
    scale = np.linalg.norm(P.max(0) - P.min(0))
    on_wall = best_d < 1e-9 * scale
    away[on_wall] = -N[best_f[on_wall]]
    away[~on_wall] /= best_d[~on_wall][:, None]
    return best_d, away


def metric_from_frame(n, h_n, h_t):
    """M = n n^T / h_n^2 + (I - n n^T) / h_t^2, per point."""
    nn = np.einsum("ij,ik->ijk", n, n)
    eye = np.eye(3)[None, :, :]
    return nn / (h_n ** 2)[:, None, None] + (eye - nn) / (h_t ** 2)[:, None, None]


def case_metric(case, X, P, F, h, wall=None):
    """Metric of a case at points X, for the tangential (base) size h; `wall`:
    wall_distance_and_normal(X, P, F) when already known."""
    lo, hi = P.min(0), P.max(0)
    centre, ext = (lo + hi) / 2, hi - lo
    diag = float(np.linalg.norm(ext))
    if case == "cyl3":
        axis = np.zeros(3)
        axis[int(np.argmax(ext))] = 1.0
        R = 0.5 * float(np.sort(ext)[1])
        rel = X - centre
        radial = rel - np.outer(rel @ axis, axis)
        r = np.linalg.norm(radial, axis=1)
        tang = np.cross(axis[None, :], radial)
        ok = r > 1e-12 * diag
        tang[ok] /= r[ok][:, None]
        h_tan = h * (1 + 2 * np.minimum(r / R, 1.0))
        M = np.eye(3)[None, :, :] / h ** 2 * np.ones((len(X), 1, 1))
        tt = np.einsum("ij,ik->ijk", tang, tang)
        M = M + tt * (1 / h_tan ** 2 - 1 / h ** 2)[:, None, None]
        return M
    if case.startswith("bl"):
        ratio = float(case[2:])
        d, n = wall if wall is not None else wall_distance_and_normal(X, P, F)
        depth = 5 * h
        h_n = h / ratio + (h - h / ratio) * np.minimum(d / depth, 1.0)
        return metric_from_frame(n, h_n, np.full(len(X), h))
    if case.startswith("shock"):
        ratio = float(case[5:])
        normal = np.array([1.0, 0.45, 0.3])
        normal /= np.linalg.norm(normal)
        s = np.abs((X - centre) @ normal)
        half = diag / 40
        h_n = np.minimum(h, h / ratio + 0.3 * np.maximum(s - half, 0.0))
        return metric_from_frame(np.tile(normal, (len(X), 1)), h_n, np.full(len(X), h))
    raise ValueError(case)


def tetgen_background(off, work, tets):
    P, F = read_off(off)
    A, B, C = P[F[:, 0]], P[F[:, 1]], P[F[:, 2]]
    volume = abs(np.einsum("ij,ij->i", A, np.cross(B, C)).sum()) / 6
    base = os.path.join(work, "bg")
    shutil.copy(off, base + ".off")
    subprocess.run(["tetgen", "-pq1.4Qa%.9g" % (volume / tets), base + ".off"],
                   check=True, stdout=subprocess.DEVNULL)
    def table(path, cols):
        with open(path) as f:
            rows = [l.split() for l in f if l.strip() and not l.startswith("#")]
        return np.array([[float(x) for x in r[1:1 + cols]] for r in rows[1:]])
    X = table(base + ".1.node", 3)
    T = table(base + ".1.ele", 4).astype(np.int64)
    T -= int(T.min())  # 0- or 1-based
    return P, F, X, T


def complexity(M, X, T):
    """Integral of sqrt(det M) over the background mesh (P1 average)."""
    s = np.sqrt(np.maximum(np.linalg.det(M), 0))
    a, b, c, d = (X[T[:, k]] for k in range(4))
    vol = np.abs(np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a))) / 6
    return float((vol * s[T].mean(1)).sum())


def write_medit(path, X, T):
    with open(path, "w") as f:
        f.write("MeshVersionFormatted 2\nDimension 3\nVertices\n%d\n" % len(X))
        f.writelines("%.17g %.17g %.17g 0\n" % tuple(x) for x in X)
        f.write("Tetrahedra\n%d\n" % len(T))
        f.writelines("%d %d %d %d 1\n" % tuple(t + 1) for t in T)
        f.write("End\n")


def write_sol(path, M):
    with open(path, "w") as f:
        f.write("MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n%d\n1 3\n" % len(M))
        f.writelines("%.17g %.17g %.17g %.17g %.17g %.17g\n" % (
            m[0, 0], m[1, 0], m[1, 1], m[2, 0], m[2, 1], m[2, 2]) for m in M)
        f.write("End\n")


def prepare(surface, case, args):
    work = os.path.join(args.out, "%s_%s" % (os.path.splitext(surface)[0], case))
    os.makedirs(work, exist_ok=True)
    P, F, X, T = tetgen_background(os.path.join(args.meshes, surface), work, args.background_tets)
    wall = wall_distance_and_normal(X, P, F) if case.startswith("bl") else None
    # about sqrt 2 nodes per unit metric volume (a packing of unit spacing);
    # the node estimate goes as h^-3 where every size scales with h (cyl3),
    # only roughly where a layer's depth or a shock's growth does not (bl,
    # shock): the vertex counts of those cases miss the target (see the table)
    c1 = complexity(case_metric(case, X, P, F, 1.0, wall), X, T)
    h = (math.sqrt(2) * c1 / args.vertices) ** (1 / 3)
    M = case_metric(case, X, P, F, h, wall)
    write_medit(os.path.join(work, "bg.mesh"), X, T)
    write_sol(os.path.join(work, "bg.sol"), M)
    return work, h


def run(surface, case, args):
    work, h = prepare(surface, case, args)
    report = os.path.join(work, "report.json")
    if os.path.exists(report):
        os.remove(report)
    cmd = [args.tool, os.path.join(args.meshes, surface), "-o", os.path.join(work, "out.mesh"),
           "--metric-mesh", os.path.join(work, "bg.mesh"), "--metric-sol", os.path.join(work, "bg.sol"),
           "--seed", "0", "--report", report, "--time-limit", str(args.time_limit),
           "--threads", str(args.threads)]
    start = time.time()
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    seconds = time.time() - start
    with open(os.path.join(work, "log.txt"), "w") as f:
        f.write(" ".join(cmd) + "\n" + proc.stdout)
    j = {}
    if os.path.exists(report):
        with open(report) as f:
            j = json.load(f)
    return dict(surface=surface, case=case, h=h, exit=proc.returncode, seconds=seconds, report=j,
                message=proc.stdout.strip().splitlines()[-1] if proc.returncode and proc.stdout.strip() else "")


# issue 18's floors: (worst metric minimum dihedral in degrees, fraction of
# metric edges in [1/sqrt2, sqrt2]) per case
FLOORS = {"cyl3": (10, 0.90), "bl4": (10, 0.90), "bl10": (10, 0.90), "shock10": (10, 0.90), "shock40": (5, 0.85)}


def problems(r, floors=True):
    """why a run fails the benchmark: no mesh, a packing stage at its cap, below the case's floors"""
    if r["exit"] != 0:
        return ["exit %d" % r["exit"]]
    j = r["report"]
    if not j:
        return ["no report"]
    m = j.get("meshing", {})
    out = []
    conv = m.get("packing_converged", [])
    settled = m.get("packing_settled", [False] * len(conv))
    stages = ["corners", "curves", "surfaces", "volume"]
    capped = [stages[k] if k < len(stages) else str(k) for k, (c, st) in enumerate(zip(conv, settled)) if not c and not st]
    if capped:
        out.append("packing at its cap: " + ", ".join(capped))
    if floors and r["case"] in FLOORS:
        worst, in_range = FLOORS[r["case"]]
        if not j["min_dihedral"]["worst"] >= worst:
            out.append("worst %.1f deg < %g" % (j["min_dihedral"]["worst"], worst))
        if not j["edge_length"]["in_range_fraction"] >= in_range:
            out.append("edges in range %.1f %% < %g %%" % (100 * j["edge_length"]["in_range_fraction"], 100 * in_range))
    return out


def row(r):
    j = r["report"]
    m = j.get("meshing", {})
    imp = m.get("improvement", {})
    if not j:
        return "| %s | %s | %d | | | | | | | | | | | %.1f |" % (r["surface"], r["case"], r["exit"], r["seconds"])
    its = m.get("packing_iterations", [])
    conv = m.get("packing_converged", [])
    settled = m.get("packing_settled", [False] * len(conv))
    it_text = "/".join("%d%s" % (i, "" if c else ("s" if st else "*")) for i, c, st in zip(its, conv, settled))
    ps = sum(m.get("packing_seconds", []))
    return "| %s | %s | %d | %d | %.1f / %.1f / %.1f / %.1f | %s | %d | %.1f | %.1f | %.3f | %.1f %% | %.1f %% | %.1f |" % (
        r["surface"], r["case"], r["exit"], j.get("vertices", 0), ps, m.get("boundary_seconds", 0),
        m.get("front_seconds", 0), imp.get("seconds", 0), it_text, m.get("added_boundary_nodes", 0),
        j["min_dihedral"]["worst"], j["min_dihedral"]["p01"], j["mean_ratio"]["worst"],
        100 * imp.get("edges_in_range_before", float("nan")),
        100 * j["edge_length"]["in_range_fraction"], r["seconds"])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tool", required=True)
    ap.add_argument("--meshes", required=True, help="CGAL's data/meshes directory")
    ap.add_argument("--out", default="/tmp/bubble_mesh_3_anisotropy")
    ap.add_argument("--surfaces", default=",".join(SURFACES))
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--vertices", type=float, default=10000)
    ap.add_argument("--background-tets", type=int, default=100000)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--time-limit", type=float, default=600)
    ap.add_argument("--table", help="write the markdown table here too")
    ap.add_argument("--no-floors", action="store_true", help="fail on exits and packing caps only")
    args = ap.parse_args()
    if shutil.which("tetgen") is None:
        sys.exit("anisotropy_family.py: needs the tetgen binary (apt-get install tetgen)")
    runs = [(s, c) for s in args.surfaces.split(",") for c in args.cases.split(",")]
    head = ("| surface | metric | exit | vertices | seconds: packing / boundary / front / improvement | "
            "packing iterations (corners/curves/surfaces/volume; * = cap) | added nodes | worst (deg) | p01 (deg) | "
            "worst mean ratio | edges in range after front | after improvement | seconds |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    lines = [head]
    print(head, flush=True)
    failures = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for r in pool.map(lambda sc: run(sc[0], sc[1], args), runs):
            line = row(r)
            lines.append(line)
            print(line + ("  " + r["message"] if r["message"] else ""), flush=True)
            why = problems(r, floors=not args.no_floors)
            if why:
                failures.append("%s %s: %s" % (r["surface"], r["case"], "; ".join(why)))
    summary = ("\n%d of %d runs fail the benchmark:\n" % (len(failures), len(runs)) +
               "\n".join("- " + f for f in failures)) if failures else "\nall %d runs pass" % len(runs)
    print(summary, flush=True)
    lines.append(summary)
    if args.table:
        with open(args.table, "w") as f:
            f.write("\n".join(lines) + "\n")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
