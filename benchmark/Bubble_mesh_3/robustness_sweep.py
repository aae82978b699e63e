#!/usr/bin/env python3
"""Robustness sweep: the command-line tool on every closed surface of CGAL's
data set x sizes x metrics x seeds, each run in its own process.

    robustness_sweep.py --tool build/bin/bubble_mesh_3 --meshes DIR [options]

For each surface the first run tells whether the input is accepted: a refusal
(exit 2: open, self-intersecting, ...) is listed with the tool's message and
the surface is skipped. Every other run must give a valid mesh (exit 0); the
table gives vertices, input vertices kept as nodes by the boundary front,
worst / p01 metric minimum dihedral angle, worst metric mean ratio, metric
edges in [1/sqrt2, sqrt2] (after the improvement, and before it), volume
error, largest distance of the boundary to the input surface, seconds. Exit status: 0 when every run on
an accepted surface gave a mesh and met the quality floors given by
--min-worst-iso / --min-worst-aniso (at sizes diag/30 and finer), 1 otherwise.

Sizes are fractions of the bounding box diagonal (--sizes 10,30,100 means
diag/10, diag/30, diag/100). Metrics: `iso` (--size h) and `aniso3` (a
constant metric with sizes h*sqrt3, h/sqrt3, h along axes rotated by 40 deg
about (1,2,3): ratio 1:3, the same node density as `iso`).
"""
import argparse
import concurrent.futures
import json
import math
import os
import subprocess
import sys
import time


def read_off_bbox_diagonal(path):
    """Bounding box diagonal of an OFF file (header variants COFF, NOFF, ...;
    the first three numbers of each vertex line)."""
    with open(path, "r", errors="replace") as f:
        lines = (l.split("#", 1)[0].split() for l in f)
        lines = (l for l in lines if l)
        head = next(lines)
        if head[0].upper().endswith("OFF"):
            head = head[1:] or next(lines)
        nv = int(head[0])
        lo = [math.inf] * 3
        hi = [-math.inf] * 3
        for _ in range(nv):
            v = next(lines)
            for k in range(3):
                x = float(v[k])
                lo[k] = min(lo[k], x)
                hi[k] = max(hi[k], x)
    return math.sqrt(sum((hi[k] - lo[k]) ** 2 for k in range(3)))


def read_off_smallest_wedge(path):
    """Smallest angle, in degrees, between the two faces at an edge of an
    OFF triangle surface, measured inside the solid (None when no edge has two
    faces). A mesh that keeps that edge has a tet with no larger dihedral
    angle there (isotropic), whatever the mesher: the target of a run is at
    most this."""
    with open(path, "r", errors="replace") as f:
        lines = [l for l in (l.split("#", 1)[0].split() for l in f) if l]
    head, i = lines[0], 1
    if head[0].upper().endswith("OFF"):  # OFF, COFF, NOFF, ...; counts on this line or the next
        head = head[1:]
        if not head:
            head, i = lines[1], 2
    nv, nf = int(head[0]), int(head[1])
    v = [tuple(float(x) for x in lines[i + k][:3]) for k in range(nv)]
    faces = []
    for line in lines[i + nv:i + nv + nf]:
        n = int(line[0])
        idx = [int(x) for x in line[1:1 + n]]
        faces.extend((idx[0], idx[j], idx[j + 1]) for j in range(1, n - 1))

    def sub(a, b):
        return (a[0] - b[0], a[1] - b[1], a[2] - b[2])

    def cross(a, b):
        return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])

    def dot(a, b):
        return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]

    normals = []
    for a, b, c in faces:
        n = cross(sub(v[b], v[a]), sub(v[c], v[a]))
        length = math.sqrt(dot(n, n))
        normals.append(tuple(x / length for x in n) if length > 0 else None)
    face_of = {}
    for fi, f in enumerate(faces):
        for k in range(3):
            face_of[(f[k], f[(k + 1) % 3])] = fi
    best = None
    for (a, b), f in face_of.items():
        g = face_of.get((b, a))
        if g is None or a > b or normals[f] is None or normals[g] is None:
            continue
        turn = math.degrees(math.acos(max(-1.0, min(1.0, dot(normals[f], normals[g])))))
        opposite = [x for x in faces[g] if x not in (a, b)][0]
        convex = dot(normals[f], sub(v[opposite], v[a])) < 0
        inside = 180 - turn if convex else 180 + turn
        best = inside if best is None else min(best, inside)
    return best


def rotated_metric(h, ratio=3.0):
    """a11,a12,a13,a22,a23,a33 of R diag(1/hu^2,1/hv^2,1/hw^2) R^T."""
    axis = [1.0, 2.0, 3.0]
    n = math.sqrt(sum(a * a for a in axis))
    x, y, z = (a / n for a in axis)
    t = math.radians(40)
    c, s = math.cos(t), math.sin(t)
    C = 1 - c
    R = [[c + x * x * C, x * y * C - z * s, x * z * C + y * s],
         [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
         [z * x * C - y * s, z * y * C + x * s, c + z * z * C]]
    r = math.sqrt(ratio)
    sizes = [h * r, h / r, h]
    S = [1 / (q * q) for q in sizes]
    M = [[sum(R[i][k] * S[k] * R[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
    return ",".join("%.17g" % v for v in (M[0][0], M[0][1], M[0][2], M[1][1], M[1][2], M[2][2]))


def run_case(tool, surface, fraction, metric, seed, out_dir, time_limit, threads=0):
    d = read_off_bbox_diagonal(surface)
    h = d / fraction
    name = "%s_d%d_%s_s%d" % (os.path.splitext(os.path.basename(surface))[0], fraction, metric, seed)
    report = os.path.join(out_dir, name + ".json")
    args = [tool, surface, "-o", os.path.join(out_dir, name + ".mesh"), "--report", report, "--seed", str(seed),
            "--quiet", "--time-limit", str(time_limit), "--threads", str(threads)]
    if metric == "iso":
        args += ["--size", "%.17g" % h]
    else:
        args += ["--metric-const", rotated_metric(h)]
    if os.path.exists(report):
        os.remove(report)
    t0 = time.time()
    p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    seconds = time.time() - t0
    row = {"surface": os.path.basename(surface), "fraction": fraction, "metric": metric, "seed": seed,
           "exit": p.returncode, "seconds": seconds, "message": p.stderr.strip().splitlines()[-1:] or [""]}
    row["message"] = row["message"][0]
    if p.returncode == 0 and os.path.exists(report):
        with open(report) as f:
            r = json.load(f)
        m = r.get("meshing", {})
        row.update(vertices=r.get("vertices"), tets=r.get("tets"), worst=r.get("min_dihedral", {}).get("worst"),
                   p01=r.get("min_dihedral", {}).get("p01"), added=m.get("added_boundary_nodes", 0),
                   mean_ratio=r.get("mean_ratio", {}).get("worst"),
                   in_range=r.get("edge_length", {}).get("in_range_fraction"),
                   in_range_front=m.get("improvement", {}).get("edges_in_range_before"),
                   volume_error=m.get("volume_error"), distance=m.get("surface_distance"),
                   distance_rel=m.get("surface_distance_relative"))
        # features finer than the feature-size floor (a tenth of the largest
        # size: h, or h sqrt3 for aniso3): the field stops refining there,
        # so what is left of them is below the resolution asked
        smallest = m.get("smallest_feature_size")
        largest = h if metric == "iso" else h * math.sqrt(3.0)
        row["floored"] = smallest is not None and 0 < smallest <= 0.1 * largest * (1 + 1e-6)
        # how often the front's fallbacks ran (issue 20: prefer the project's own recovery)
        row["fallbacks"] = {k: m.get(k, 0) for k in ("best_quality_tets", "undo_rounds", "cavities",
                                                     "vertex_star_fills", "steiner_star_fills", "tetgen_fills",
                                                     "cavity_enlargements", "steiner_points")}
    for ext in (".mesh",):
        try:
            os.remove(os.path.join(out_dir, name + ext))
        except OSError:
            pass
    return row


def fmt(x, spec):
    return "-" if x is None else format(x, spec)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tool", required=True)
    ap.add_argument("--meshes", required=True, help="folder of CGAL's data/meshes")
    ap.add_argument("--surfaces", default="", help="comma-separated file names (default: every .off)")
    ap.add_argument("--sizes", default="10,30,100")
    ap.add_argument("--metrics", default="iso,aniso3")
    ap.add_argument("--seeds", default="0,1")
    ap.add_argument("--time-limit", type=float, default=600)
    ap.add_argument("--out-dir", default=os.path.join(os.environ.get("TMPDIR", "/tmp"), "bubble_mesh_3_sweep"))
    ap.add_argument("--table", default="", help="write the markdown table here (default: stdout)")
    ap.add_argument("--min-worst-iso", type=float, default=0.0)
    ap.add_argument("--min-worst-aniso", type=float, default=0.0)
    ap.add_argument("--jobs", type=int, default=1, help="runs at once (each with one packing thread when > 1)")
    a = ap.parse_args()
    os.makedirs(a.out_dir, exist_ok=True)
    if a.surfaces:
        surfaces = [os.path.join(a.meshes, s) for s in a.surfaces.split(",")]
    else:
        surfaces = sorted(os.path.join(a.meshes, s) for s in os.listdir(a.meshes) if s.endswith(".off"))
    sizes = [int(s) for s in a.sizes.split(",")]
    metrics = a.metrics.split(",")
    seeds = [int(s) for s in a.seeds.split(",")]
    rows, refused = [], []
    failures = 0

    def report(row):
        nonlocal failures
        bad = row["exit"] != 0
        floor = a.min_worst_iso if row["metric"] == "iso" else a.min_worst_aniso
        if row["metric"] == "iso" and wedges.get(row["surface"]) is not None:
            floor = min(floor, wedges[row["surface"]])  # no mesh keeping the input's edges does better
        if not bad and row["fraction"] >= 30 and row.get("worst") is not None and row["worst"] < floor:
            bad = True
            row["below_floor"] = True
        failures += bad
        sys.stderr.write("%-28s d/%-3d %-6s seed %d: exit %d, %s, %.1f s%s\n" % (
            row["surface"], row["fraction"], row["metric"], row["seed"], row["exit"],
            "worst %s" % fmt(row.get("worst"), ".1f") if row["exit"] == 0 else row["message"][:120],
            row["seconds"], " BELOW FLOOR" if row.get("below_floor") else ""))

    wedges = {}
    for surface in surfaces:
        try:
            wedges[os.path.basename(surface)] = read_off_smallest_wedge(surface)
        except Exception:  # an unreadable file is the tool's to refuse; the column shows "-"
            wedges[os.path.basename(surface)] = None

    # the first run of each surface tells whether the input is accepted
    threads = 1 if a.jobs > 1 else 0
    first_config = (sizes[0], metrics[0], seeds[0])
    accepted = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
        firsts = list(pool.map(lambda s: run_case(a.tool, s, *first_config, a.out_dir, a.time_limit, threads),
                               surfaces))
        for surface, row in zip(surfaces, firsts):
            if row["exit"] == 2:
                refused.append(row)
            else:
                accepted.append(surface)
                rows.append(row)
                report(row)
        rest = [(s, f, m, k) for s in accepted for f in sizes for m in metrics for k in seeds
                if (f, m, k) != first_config]
        for row in pool.map(lambda c: run_case(a.tool, *c, a.out_dir, a.time_limit, threads), rest):
            rows.append(row)
            report(row)
    rows.sort(key=lambda r: (r["surface"], r["fraction"], metrics.index(r["metric"]), r["seed"]))
    lines = ["| surface | input wedge (deg) | size | metric | seed | exit | vertices | added nodes | worst (deg) | "
             "p01 (deg) | worst mean ratio | edges in range (front) | volume error | distance / diag | seconds |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    def percent(x):
        return "-" if x is None else "%.1f %%" % (100 * x)
    for r in rows:
        ve = r.get("volume_error")
        lines.append("| %s | %s | d/%d | %s | %d | %d%s | %s | %s | %s | %s | %s | %s (%s) | %s | %s | %.1f |" % (
            r["surface"], fmt(wedges.get(r["surface"]), ".1f"), r["fraction"], r["metric"], r["seed"], r["exit"],
            (" (" + r["message"][:80].replace("|", "/") + ")") if r["exit"] else "",
            fmt(r.get("vertices"), "d"), fmt(r.get("added"), "d"), fmt(r.get("worst"), ".1f"), fmt(r.get("p01"), ".1f"),
            fmt(r.get("mean_ratio"), ".3f"), percent(r.get("in_range")), percent(r.get("in_range_front")),
            "-" if ve is None else "%.2f %%" % (100 * ve), fmt(r.get("distance_rel"), ".2e"), r["seconds"]))
    ok = sum(1 for r in rows if r["exit"] == 0)
    signalled = [r for r in rows if r["exit"] < 0]
    lines.append("")
    keys = ("best_quality_tets", "undo_rounds", "cavities", "vertex_star_fills", "steiner_star_fills",
            "tetgen_fills", "cavity_enlargements", "steiner_points")
    totals = {k: sum(r.get("fallbacks", {}).get(k, 0) for r in rows) for k in keys}
    runs_with = {k: sum(1 for r in rows if r.get("fallbacks", {}).get(k, 0) > 0) for k in keys}
    lines.append("Front fallbacks over the valid runs (total, and runs where each ran): " + ", ".join(
        "%s %d (%d runs)" % (k.replace("_", " "), totals[k], runs_with[k]) for k in keys) + ".")
    tetgen_runs = [r for r in rows if r.get("fallbacks", {}).get("tetgen_fills", 0) > 0]
    if tetgen_runs:
        lines.append("")
        lines.append("Runs whose front called TetGen: " + ", ".join(
            "%s d/%d %s s%d" % (r["surface"], r["fraction"], r["metric"], r["seed"]) for r in tetgen_runs) + ".")
    floored = [r for r in rows if r.get("floored")]
    if floored:
        lines.append("")
        lines.append("Runs with features finer than a tenth of the size (feature sizes raised to that floor, "
                     "the elements there are larger than the features): " + ", ".join(
                         "%s d/%d %s s%d (worst %s)" % (r["surface"], r["fraction"], r["metric"], r["seed"],
                                                        fmt(r.get("worst"), ".1f")) for r in floored) + ".")
    lines.append("")
    lines.append("Runs ended by a signal: %d%s." % (len(signalled), "".join(
        " %s d/%d %s s%d (signal %d)" % (r["surface"], r["fraction"], r["metric"], r["seed"], -r["exit"])
        for r in signalled)))
    lines.append("")
    lines.append("%d runs on %d accepted surfaces: %d valid meshes, %d failures (exit != 0 or below the floor)." % (
        len(rows), len(surfaces) - len(refused), ok, failures))
    if refused:
        lines.append("")
        lines.append("Refused inputs (exit 2, the tool's message):")
        lines.append("")
        for r in refused:
            lines.append("- %s: %s" % (r["surface"], r["message"].replace("bubble_mesh_3: error: ", "")))
    text = "\n".join(lines) + "\n"
    if a.table:
        with open(a.table, "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
