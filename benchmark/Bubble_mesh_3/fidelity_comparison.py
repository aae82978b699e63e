#!/usr/bin/env python3
"""Surface fidelity against CGAL Mesh_3 at equal vertex counts (issue 13).

For each surface of CGAL's data set given (fetched at run time, never
committed), at size h = bounding-box diagonal / FRACTION and distance bound
D = h / DISTANCE_FRACTION:

  ours      bubble_mesh_3 SURFACE --size h --surface-distance D
  Mesh_3    make_mesh_3 with facet_distance = D, its size s fitted so that its
            vertex count is ours within +-10 % (bench_quality_competitors
            --only mesh3 --facet-distance D), perturb + exude
  ours, no bound   bubble_mesh_3 SURFACE --size h (for reference)

Every mesh is evaluated by the same code, `bubble_mesh_3 eval MESH --size h
--surface SURFACE`: volume error |V_mesh - V_input| / V_input, the largest
distance of the boundary to the input (sampled over each boundary triangle),
the worst isotropic minimum dihedral angle. Writes a Markdown table.
"""
import argparse
import json
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from robustness_sweep import read_off_bbox_diagonal  # noqa: E402


def run(args, timeout):
    t0 = time.time()
    p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout)
    return p.returncode, time.time() - t0, p.stderr.strip().splitlines()[-1:] or [""]


def evaluate(tool, mesh, h, surface, out):
    code, _, msg = run([tool, "eval", mesh, "--size", "%.17g" % h, "--surface", surface, "--report", out, "--quiet"],
                       600)
    if code != 0:
        return None
    with open(out) as f:
        j = json.load(f)
    return dict(vertices=j["vertices"], worst=j["min_dihedral"]["worst"], volume_error=j["surface"]["volume_error"],
                distance=j["surface"]["surface_distance"], valid=j["validity"]["valid"])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tool", required=True)
    ap.add_argument("--competitors", required=True, help="bench_quality_competitors")
    ap.add_argument("--meshes", required=True, help="CGAL's data/meshes folder")
    ap.add_argument("--out-dir", required=True)
    ap.add_argument("--surfaces", default="eight,knot1,cactus,elephant,fandisk,dino,triceratops,femur")
    ap.add_argument("--fraction", type=float, default=30)
    ap.add_argument("--distance-fraction", type=float, default=10)
    ap.add_argument("--table", required=True)
    a = ap.parse_args()
    os.makedirs(a.out_dir, exist_ok=True)
    rows = []
    for name in a.surfaces.split(","):
        surface = os.path.join(a.meshes, name + ".off")
        h = read_off_bbox_diagonal(surface) / a.fraction
        d = h / a.distance_fraction
        row = dict(surface=name, h=h, d=d)
        for key, extra in (("ours", ["--surface-distance", "%.17g" % d]), ("plain", [])):
            mesh = os.path.join(a.out_dir, "%s_%s.mesh" % (name, key))
            code, seconds, msg = run([a.tool, surface, "-o", mesh, "--size", "%.17g" % h, "--seed", "0", "--quiet"]
                                     + extra, 900)
            row[key] = evaluate(a.tool, mesh, h, surface, mesh + ".eval.json") if code == 0 else None
            if row[key] is not None:
                row[key]["seconds"] = seconds
            else:
                row[key + "_error"] = "exit %d: %s" % (code, msg[0])
        if row["ours"] is not None:
            prefix = os.path.join(a.out_dir, name)
            code, seconds, msg = run([a.competitors, surface, str(row["ours"]["vertices"]), prefix, "--only", "mesh3",
                                      "--facet-distance", "%.17g" % d, "--max-runs", "6"], 3600)
            mesh = prefix + "_mesh3.mesh"
            row["mesh3"] = evaluate(a.tool, mesh, h, surface, mesh + ".eval.json") if os.path.exists(mesh) else None
            if row["mesh3"] is not None:
                with open(prefix + "_competitors.json") as f:
                    c = json.load(f)
                m = c.get("mesh3", {})
                row["mesh3"]["seconds"] = m.get("seconds")  # the kept run's make_mesh_3
                row["mesh3"]["in_band"] = m.get("in_band")
        rows.append(row)
        sys.stderr.write("%s: %s\n" % (name, json.dumps({k: row.get(k) for k in ("ours", "mesh3", "plain")})))

    def cells(r, d):
        if r is None:
            return "- | - | - | - | - | -"
        vertices = "%d" % r["vertices"] + ("" if r.get("in_band", True) else " (not ±10 %)")
        return "%s | %.2f %% | %.2f | %.1f | %s | %s" % (
            vertices, 100 * r["volume_error"], r["distance"] / d, r["worst"],
            "yes" if r["valid"] else "**no**", "-" if r.get("seconds") is None else "%.1f" % r["seconds"])
    lines = ["| surface | h | D | ours: vertices | volume error | distance / D | worst (deg) | valid | s | "
             "Mesh_3: vertices | volume error | distance / D | worst (deg) | valid | s | "
             "ours without bound: vertices | volume error | distance / D | worst (deg) | valid | s |",
             "|---" * 21 + "|"]
    for r in rows:
        lines.append("| %s | %.4g | %.3g | %s | %s | %s |" % (r["surface"], r["h"], r["d"], cells(r.get("ours"), r["d"]),
                                                            cells(r.get("mesh3"), r["d"]), cells(r.get("plain"), r["d"])))
    with open(a.table, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
