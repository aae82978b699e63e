#!/usr/bin/env bash
# Quality comparison of bubble_mesh_3 with CGAL Mesh_3 (perturb + exude) and
# TetGen (-pq1.414 -a<maxvol>) at equal vertex counts (issue 6), results in
# benchmark/Bubble_mesh_3/RESULTS_quality.md.
#
#   benchmark/Bubble_mesh_3/run_quality_comparison.sh [OUT_DIR]
#
# For each case: mesh with our CLI, then with the two competitors at our vertex
# count (bench_quality_competitors, +-10 % by a few runs), evaluate every mesh
# in the same metric (`bubble_mesh_3 eval ... --report`; the boundary-layer
# metric, which eval does not offer, with `bench_quality_competitors
# eval-boundary-layer`, the same report code), and write OUT_DIR/table.md.
# Bulky outputs (.mesh, .json, .svg) go to OUT_DIR (default
# ${TMPDIR:-/tmp}/bubble_mesh_3_quality); nothing is written into the tree.
#
# Environment:
#   CGAL_DATA_DIR  a folder holding data/meshes/{fandisk,elephant}.off (CGAL's data set);
#                  otherwise it is fetched once with `apt-get download libcgal-demo`
#                  into ${XDG_CACHE_HOME:-~/.cache}/bubble_mesh_3/cgal_data
#   BUILD_DIR      build folder (default: <repo>/build)
#   QBENCH_BUILD   setup (default): scripts/setup with benchmarks on (builds everything);
#                  targets: configure and build only the two programs used here;
#                  none: use the binaries already in BUILD_DIR/bin
#   CASES          subset of "cylinder fandisk fandisk_cyl elephant elephant_bl"
#   TABLE_ONLY=1   only rewrite OUT_DIR/table.md from the outputs already there
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
out="${1:-${TMPDIR:-/tmp}/bubble_mesh_3_quality}"
build="${BUILD_DIR:-$here/build}"
cases="${CASES:-cylinder fandisk fandisk_cyl elephant elephant_bl}"
mkdir -p "$out"
command -v python3 >/dev/null || { echo "run_quality_comparison: needs python3 (apt-get install python3)" >&2; exit 1; }

# ---- CGAL's data set, fetched at run time (never committed)
find_cgal_data() {
  local d
  for d in "${CGAL_DATA_DIR:-}" "${XDG_CACHE_HOME:-$HOME/.cache}/bubble_mesh_3/cgal_data"; do
    if [ -n "$d" ] && [ -f "$d/data/meshes/fandisk.off" ] && [ -f "$d/data/meshes/elephant.off" ]; then
      echo "$d"
      return
    fi
  done
  d="${XDG_CACHE_HOME:-$HOME/.cache}/bubble_mesh_3/cgal_data"
  local tmp
  tmp="$(mktemp -d)"
  chmod 755 "$tmp" # apt's sandbox user must be able to write the .deb
  echo "run_quality_comparison: fetching CGAL's data set (libcgal-demo) into $d" >&2
  (cd "$tmp" && apt-get download libcgal-demo >/dev/null && dpkg -x libcgal-demo_*.deb x) >&2
  local tarball
  tarball="$(find "$tmp/x" -name data.tar.gz | head -n 1)"
  [ -n "$tarball" ] || { echo "run_quality_comparison: no data.tar.gz in libcgal-demo" >&2; exit 1; }
  mkdir -p "$d"
  tar -xzf "$tarball" -C "$d" data/meshes/fandisk.off data/meshes/elephant.off
  rm -rf "$tmp"
  echo "$d"
}
meshes="$(find_cgal_data)/data/meshes"

# ---- build
case "${QBENCH_BUILD:-setup}" in
  setup) "$here/scripts/setup" "$build" Release -DBUBBLE_MESH_3_BUILD_BENCHMARKS=ON ;;
  targets)
    cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release -DBUBBLE_MESH_3_BUILD_BENCHMARKS=ON >/dev/null
    cmake --build "$build" --target bubble_mesh_3 bench_quality_competitors -j1 ;;
  none) ;;
  *) echo "run_quality_comparison: QBENCH_BUILD must be setup, targets or none" >&2; exit 1 ;;
esac
tool="$build/bin/bubble_mesh_3"
competitors="$build/bin/bench_quality_competitors"
[ -x "$tool" ] && [ -x "$competitors" ] || { echo "run_quality_comparison: missing $tool or $competitors" >&2; exit 1; }

now() { date +%s.%N; }

# ours NAME SURFACE MESH_ARGS... : meshes; writes NAME.mesh, NAME.mesh.json, NAME_section.svg, NAME.status
ours() {
  local name="$1" surface="$2"
  shift 2
  local t0 rc=0
  t0="$(now)"
  "$tool" "$surface" -o "$out/$name.mesh" "$@" --report "$out/$name.mesh.json" \
    --section "$out/${name}_section.svg" --histogram "$out/${name}_histogram.svg" \
    >"$out/$name.stdout" 2>"$out/$name.stderr" || rc=$?
  python3 - "$out/$name.status" "$rc" "$t0" "$(now)" "$out/$name.stderr" <<'EOF'
import json, sys
path, rc, t0, t1, err = sys.argv[1:]
lines = [l.strip() for l in open(err) if l.strip()]
json.dump({"exit": int(rc), "wall_seconds": float(t1) - float(t0),
           "message": lines[-1] if rc != "0" and lines else ""}, open(path, "w"))
EOF
  echo "ours $name: exit $rc" >&2
  return 0
}

# evaluate MESH_PATH REPORT METRIC_KIND METRIC_ARGS: the same evaluation for every mesher
evaluate() {
  local mesh="$1" report="$2" kind="$3" args="$4" surface="${5:-}"
  case "$kind" in
    size) "$tool" eval "$mesh" --size "$args" --report "$report" --quiet ;;
    cylindrical) "$tool" eval "$mesh" --metric-cylindrical "$args" --report "$report" --quiet ;;
    boundary-layer) "$competitors" eval-boundary-layer "$mesh" "$surface" "$args" --report "$report" >/dev/null ;;
  esac
}

# run_case NAME SURFACE METRIC_KIND METRIC_ARGS SIZE0: ours, then the competitors at our vertex count
run_case() {
  local name="$1" surface="$2" kind="$3" args="$4" size0="$5"
  echo "== $name ==" >&2
  local metric_opt
  case "$kind" in
    size) metric_opt=(--size "$args") ;;
    cylindrical) metric_opt=(--metric-cylindrical "$args") ;;
    boundary-layer) metric_opt=(--metric-boundary-layer "$args") ;;
  esac
  ours "${name}_ours" "$surface" "${metric_opt[@]}"
  if [ ! -f "$out/${name}_ours.mesh" ] || [ "$(python3 -c "import json,sys;print(json.load(open(sys.argv[1]))['exit'])" "$out/${name}_ours.status")" != 0 ]; then
    echo "$name: our mesher failed, competitors skipped" >&2
    return 0
  fi
  evaluate "$out/${name}_ours.mesh" "$out/${name}_ours.eval.json" "$kind" "$args" "$surface"
  local n
  n="$(python3 -c "import json,sys;print(json.load(open(sys.argv[1]))['vertices'])" "$out/${name}_ours.eval.json")"
  local rc=0
  "$competitors" "$surface" "$n" "$out/$name" --size0 "$size0" >"$out/${name}_competitors.stdout" \
    2>"$out/${name}_competitors.stderr" || rc=$?
  echo "competitors $name ($n vertices): exit $rc" >&2
  local m
  for m in mesh3 tetgen tetgen_remeshed; do
    if [ -f "$out/${name}_$m.mesh" ]; then
      evaluate "$out/${name}_$m.mesh" "$out/${name}_$m.eval.json" "$kind" "$args" "$surface" || true
    fi
  done
}

cylinder="$here/examples/Bubble_mesh_3/data/cylinder.off"
# fandisk: bounding box [-0.46,0.46] x [-0.256,0.256] x [-0.5,0.5]; the axis runs
# along its longest side (z) through the box centre; 1:3 reached at r = 0.4.
fandisk_cyl="0,0,0,0,0,1,0.03,3,0.4"
# elephant: tangential size 0.03, normal 0.03/4 on the surface, back to 1:1 at depth 0.06
# (0.00625,0.025,0.05 fails: exit 3 "advancing front: TetGen lost a cavity triangle")
elephant_bl="0.0075,0.03,0.06"
for c in $cases; do
  [ -z "${TABLE_ONLY:-}" ] || break
  case "$c" in
    cylinder) run_case cylinder "$cylinder" size 0.19 0.16 ;;
    fandisk) run_case fandisk "$meshes/fandisk.off" size 0.03 0.025 ;;
    fandisk_cyl) run_case fandisk_cyl "$meshes/fandisk.off" cylindrical "$fandisk_cyl" 0.025 ;;
    elephant) run_case elephant "$meshes/elephant.off" size 0.025 0.02 ;;
    elephant_bl) run_case elephant_bl "$meshes/elephant.off" boundary-layer "$elephant_bl" 0.015 ;;
    *) echo "run_quality_comparison: unknown case $c" >&2; exit 1 ;;
  esac
done

# ---- the table
python3 - "$out" $cases >"$out/table.md" <<'EOF'
import json, os, sys
out, cases = sys.argv[1], sys.argv[2:]
metric_label = {"cylinder": "isotropic 0.19", "fandisk": "isotropic 0.03",
                "fandisk_cyl": "cylindrical 1:3 (H 0.03, R 0.4, axis z)",
                "elephant": "isotropic 0.025", "elephant_bl": "boundary layer 1:4 (0.0075, 0.03, 0.06)"}
anisotropic = {"fandisk_cyl", "elephant_bl"}
references = {  # quoted, not measured here
    "cylinder": ["| cylinder | Mesh_3 perturb+exude (issue's number) | | ~2,400 | | | 13.7 | | | | | |",
                 "| cylinder | paper (Yamakawa & Shimada) | | ~2,400 | | | 14.2 | | | | | |"],
    "fandisk_cyl": ["| fandisk_cyl | MMG3D (issue's number) | 1:3 | | | | 13.8 | 26.9 | | | 91 | |",
                    "| fandisk_cyl | paper, mechanical part | 1:3 | | | | 8.0 | | | | | |"],
    "elephant_bl": ["| elephant_bl | MMG3D (issue's number) | 1:4 | | | | 5.5 | 16.5 | | | 83 | |"],
}
def load(p):
    return json.load(open(p)) if os.path.exists(p) else None
print("| case | mesher | metric | vertices | tets | time (s) | worst (deg) | p01 (deg) | % tets < 25 deg | "
      "histogram peak bin (deg) | % edges in [1/sqrt2, sqrt2] | valid |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
for c in cases:
    rows = []
    status = load(f"{out}/{c}_ours.status")
    comp = load(f"{out}/{c}_competitors.json") or {}
    for mesher, label in (("ours", "bubble_mesh_3"), ("mesh3", "CGAL Mesh_3 perturb+exude"),
                          ("tetgen", "TetGen -pq1.414"),
                          ("tetgen_remeshed", "TetGen -pq1.414, surface remeshed (PMP)")):
        ev = load(f"{out}/{c}_{mesher}.eval.json")
        metric = metric_label.get(c, "")
        if mesher != "ours" and c in anisotropic:
            label += " (isotropic mesher)"
        if ev is None:
            if mesher == "ours" and status:
                rows.append(f"| {c} | {label} | {metric} | FAILED: exit {status['exit']}, {status['message']} "
                            "| | | | | | | | |")
            elif mesher in comp:
                rows.append(f"| {c} | {label} | {metric} | no mesh: {comp[mesher].get('note', '')} | | | | | | | | |")
            continue
        if mesher == "ours":
            seconds = load(f"{out}/{c}_ours.mesh.json")["meshing"]["total_seconds"]
        else:
            r = comp.get(mesher, {})
            seconds = r.get("seconds", float("nan"))
            if not r.get("in_band", True):
                label += " (vertex count off target)"
        hist = ev["histogram_5deg"]
        below25 = 100.0 * sum(hist[:5]) / ev["tets"]
        peak = max(range(len(hist)), key=lambda i: hist[i])
        md = ev["min_dihedral"]
        valid = ev.get("validity", {}).get("valid")
        rows.append(f"| {c} | {label} | {metric} | {ev['vertices']} | {ev['tets']} | {seconds:.2f} | "
                    f"{md['worst']:.1f} | {md['p01']:.1f} | {below25:.2f} | {5 * peak}-{5 * peak + 5} | "
                    f"{100 * ev['edge_length']['in_range_fraction']:.1f} | {'yes' if valid else valid} |")
    rows += references.get(c, [])
    print("\n".join(rows))
EOF
cat "$out/table.md"
echo "outputs in $out" >&2
