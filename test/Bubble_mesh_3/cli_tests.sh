#!/usr/bin/env bash
# End-to-end tests of the bubble_mesh_3 command: exit codes, one-line error
# messages naming the problem, outputs written (and not left behind on failure).
#   cli_tests.sh TOOL DATA_DIR WORK_DIR
set -u
tool="$1"
data="$2"
work="$3"
rm -rf "$work"
mkdir -p "$work"
passed=0
failed=0

# expect NAME EXPECTED_EXIT STDERR_PATTERN -- command args...
expect() {
  local name="$1" code="$2" pattern="$3"
  shift 4
  "$@" >"$work/out.txt" 2>"$work/err.txt"
  local got=$?
  local ok=1
  if [ "$got" -ne "$code" ]; then ok=0; fi
  if [ -n "$pattern" ] && ! grep -qE -- "$pattern" "$work/err.txt"; then ok=0; fi
  # Errors are exactly one line on stderr.
  if [ "$code" -ne 0 ] && [ "$(wc -l <"$work/err.txt")" -ne 1 ]; then ok=0; fi
  if [ $ok -eq 1 ]; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    echo "FAIL: $name (exit $got, expected $code; stderr pattern '$pattern')"
    sed 's/^/  stderr: /' "$work/err.txt" | head -5
  fi
}

check() {
  local name="$1"
  shift
  if "$@"; then passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAIL: $name"; fi
}

json_value() { # FILE KEY -> first number after "KEY":
  grep -oE "\"$2\"[[:space:]]*:[[:space:]]*-?[0-9.eE+-]+" "$1" | head -1 | sed -E 's/.*:[[:space:]]*//'
}

cube="$data/cube6.mesh"

expect help 0 "" -- "$tool" --help
check "help mentions eval" grep -q "bubble_mesh_3 eval" "$work/out.txt"
expect no-args 2 "missing command" -- "$tool"
expect unknown-command-is-a-missing-surface 2 "frobnicate" -- "$tool" frobnicate -o "$work/x.mesh"
expect unknown-option 2 "unknown option '--bogus'" -- "$tool" eval "$cube" --bogus

# A good evaluation: the unit cube in 6 tets (Kuhn), identity metric.
expect eval-cube 0 "" -- "$tool" eval "$cube" --report "$work/cube.json" --vtu "$work/cube.vtu" \
  --histogram "$work/cube.svg"
check "json tets = 6" [ "$(json_value "$work/cube.json" tets)" = "6" ]
check "json vertices = 8" [ "$(json_value "$work/cube.json" vertices)" = "8" ]
check "json inverted = 0" [ "$(json_value "$work/cube.json" inverted_tets)" = "0" ]
vol="$(json_value "$work/cube.json" volume)"
check "json volume = 1 ($vol)" awk -v v="$vol" 'BEGIN { exit !(v > 0.999999999 && v < 1.000000001) }'
# Kuhn tets have minimum dihedral angle 45 degrees in the identity metric.
worst="$(json_value "$work/cube.json" worst)"
check "worst min dihedral = 45 ($worst)" awk -v v="$worst" 'BEGIN { exit !(v > 44.999 && v < 45.001) }'
check "histogram key present" grep -q '"histogram_5deg"' "$work/cube.json"
check "vtu has 6 cells" grep -q 'NumberOfCells="6"' "$work/cube.vtu"
check "vtu has quality" grep -q 'min_dihedral' "$work/cube.vtu"
check "svg written" grep -q '<svg' "$work/cube.svg"
check "summary printed" grep -qi "dihedral" "$work/out.txt"
check "json says valid" grep -qE '"valid"[[:space:]]*:[[:space:]]*true' "$work/cube.json"
expect require-valid-ok 0 "" -- "$tool" eval "$cube" --require-valid --quiet

# An inverted tet: evaluation still reports, --require-valid refuses with exit 2.
awk 'BEGIN{t=0} /^Tetrahedra/{t=1} t==1 && NF==5 && !done {print $2, $1, $3, $4, $5; done=1; next} {print}' \
  "$cube" >"$work/inverted.mesh"
expect eval-inverted 0 "" -- "$tool" eval "$work/inverted.mesh" --report "$work/inv.json" --quiet
check "inverted counted" [ "$(json_value "$work/inv.json" inverted_tets)" = "1" ]
check "json says invalid" grep -qE '"valid"[[:space:]]*:[[:space:]]*false' "$work/inv.json"
expect require-valid-refuses 2 "inverted.mesh: invalid mesh" -- "$tool" eval "$work/inverted.mesh" --require-valid --quiet

# Stretching the cube by the metric changes the angles: diag(1,1,4) halves z lengths' room.
expect eval-stretched 0 "" -- "$tool" eval "$cube" --metric-const 1,0,0,1,0,4 --report "$work/cube4.json" --quiet
worst4="$(json_value "$work/cube4.json" worst)"
check "stretched worst differs from 45 ($worst4)" awk -v v="$worst4" 'BEGIN { exit !(v < 44 || v > 46) }'
check "quiet prints nothing" [ ! -s "$work/out.txt" ]

# Interpolated metric from a background mesh + .sol (the cube itself, identity at every vertex).
{
  printf 'MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n8\n1 3\n'
  for i in 1 2 3 4 5 6 7 8; do printf '1 0 1 0 0 1\n'; done
  printf 'End\n'
} >"$work/identity.sol"
expect eval-interpolated 0 "" -- "$tool" eval "$cube" --metric-mesh "$cube" --metric-sol "$work/identity.sol" \
  --report "$work/cube_i.json" --quiet
check "interpolated identity = identity" [ "$(json_value "$work/cube_i.json" worst)" = "$worst" ]

# Bad input: exit 2, one line naming the problem.
expect missing-file 2 "nonexistent.mesh" -- "$tool" eval "$work/nonexistent.mesh"
head -c 120 "$cube" >"$work/truncated.mesh"
expect truncated 2 "truncated.mesh:[0-9]+" -- "$tool" eval "$work/truncated.mesh"
expect not-spd 2 "not positive definite" -- "$tool" eval "$cube" --metric-const 1,2,0,1,0,1
expect nan-metric 2 "NaN" -- "$tool" eval "$cube" --metric-const 1,0,0,nan,0,1
expect metric-count 2 "6 comma-separated" -- "$tool" eval "$cube" --metric-const 1,0,0,1
expect metric-text 2 "not a number" -- "$tool" eval "$cube" --metric-const 1,0,0,x,0,1
expect bad-size 2 "size" -- "$tool" eval "$cube" --size -1
expect two-metrics 2 "at most one" -- "$tool" eval "$cube" --size 1 --metric-const 1,0,0,1,0,1
expect sol-without-mesh 2 "go together" -- "$tool" eval "$cube" --metric-sol "$work/identity.sol"
{
  printf 'MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n7\n1 3\n'
  for i in 1 2 3 4 5 6 7; do printf '1 0 1 0 0 1\n'; done
  printf 'End\n'
} >"$work/short.sol"
expect sol-count 2 "short.sol" -- "$tool" eval "$cube" --metric-mesh "$cube" --metric-sol "$work/short.sol"
sed 's/^1 0 1 0 0 1$/1 0 -1 0 0 1/' "$work/identity.sol" >"$work/bad.sol"
expect sol-not-spd 2 "bad.sol.*vertex 1" -- "$tool" eval "$cube" --metric-mesh "$cube" --metric-sol "$work/bad.sol"

# A failed write leaves no file behind under the final name.
expect unwritable-report 2 "" -- "$tool" eval "$cube" --report "$work/no/such/dir/r.json" --quiet
check "no partial report" [ ! -e "$work/no/such/dir/r.json" ]

# convert
expect convert-vtu 0 "" -- "$tool" convert "$cube" "$work/c.vtu"
check "converted vtu has 8 points" grep -q 'NumberOfPoints="8"' "$work/c.vtu"
expect convert-mesh 0 "" -- "$tool" convert "$cube" "$work/c.mesh"
expect roundtrip-eval 0 "" -- "$tool" eval "$work/c.mesh" --report "$work/c.json" --quiet
check "round-tripped mesh evaluates the same" [ "$(json_value "$work/c.json" worst)" = "$worst" ]
expect convert-bad-ext 2 "must end in" -- "$tool" convert "$cube" "$work/c.txt"

# Meshing a surface: the unit cube as 12 triangles.
{
  printf 'OFF\n8 12 0\n'
  for k in 0 1 2 3 4 5 6 7; do printf '%d %d %d\n' $((k & 1)) $(((k >> 1) & 1)) $(((k >> 2) & 1)); done
  printf '3 0 2 3\n3 0 3 1\n3 4 5 7\n3 4 7 6\n3 0 1 5\n3 0 5 4\n3 2 6 7\n3 2 7 3\n3 0 4 6\n3 0 6 2\n3 1 3 7\n3 1 7 5\n'
} >"$work/cube.off"
expect mesh-cube 0 "" -- "$tool" "$work/cube.off" -o "$work/m.mesh" --size 0.3 --vtu "$work/m.vtu" \
  --report "$work/m.json" --histogram "$work/m.svg" --section "$work/m_section.svg" --section-plane z=0.5 --seed 2
check "mesh written" [ -s "$work/m.mesh" ]
check "progress on stderr" grep -q "advancing front" "$work/err.txt"
check "summary on stdout" grep -q "min dihedral" "$work/out.txt"
check "report has meshing counters" grep -q '"steiner_points"' "$work/m.json"
check "section drawn" grep -q '<polygon' "$work/m_section.svg"
check "vtu has quality" grep -q 'min_dihedral' "$work/m.vtu"
expect meshed-cube-is-valid 0 "" -- "$tool" eval "$work/m.mesh" --size 0.3 --require-valid --report "$work/mv.json" --quiet
mvol="$(json_value "$work/mv.json" volume)"
check "meshed cube volume = 1 ($mvol)" awk -v v="$mvol" 'BEGIN { exit !(v > 0.999999999 && v < 1.000000001) }'
expect mesh-same-seed-same-mesh 0 "" -- "$tool" "$work/cube.off" -o "$work/m2.mesh" --size 0.3 --seed 2 --threads 1 --quiet
check "same seed, 1 thread: identical file" cmp -s "$work/m.mesh" "$work/m2.mesh"
expect mesh-cylindrical 0 "" -- "$tool" "$work/cube.off" -o "$work/mc.mesh" --metric-cylindrical 0.5,0.5,0,0,0,1,0.25,3,0.5 --quiet
expect mesh-boundary-layer 0 "" -- "$tool" "$work/cube.off" -o "$work/mb.mesh" --metric-boundary-layer 0.1,0.3,0.2 --quiet
# bad meshing input: exit 2, one line, no output file
head -n 12 "$work/cube.off" | sed 's/^OFF$/OFF/' | awk 'NR==2{print "8 11 0"; next} {print}' >"$work/open.off"
expect mesh-open-surface 2 "open.off" -- "$tool" "$work/open.off" -o "$work/open.mesh" --quiet
check "no output for an open surface" [ ! -e "$work/open.mesh" ]
expect mesh-missing-o 2 "missing -o" -- "$tool" "$work/cube.off" --size 0.3
expect mesh-bad-o 2 "must end in .mesh" -- "$tool" "$work/cube.off" -o "$work/m.txt"
expect mesh-too-many 2 "exceeds" -- "$tool" "$work/cube.off" -o "$work/big.mesh" --size 0.3 --max-nodes 10 --quiet
check "no output when refused" [ ! -e "$work/big.mesh" ]
expect mesh-bad-metric 2 "not positive definite" -- "$tool" "$work/cube.off" -o "$work/x.mesh" --metric-const 1,2,0,1,0,1 --quiet
expect mesh-bad-cylindrical 2 "cylindrical" -- "$tool" "$work/cube.off" -o "$work/x.mesh" --metric-cylindrical 0,0,0,0,0,0,0.2,3,1 --quiet
expect mesh-bad-plane 2 "section-plane" -- "$tool" "$work/cube.off" -o "$work/x.mesh" --section "$work/s.svg" --section-plane w=3 --quiet
expect mesh-bad-angle 2 "feature-angle" -- "$tool" "$work/cube.off" -o "$work/x.mesh" --feature-angle 200 --quiet
expect mesh-bad-threads 2 "threads" -- "$tool" "$work/cube.off" -o "$work/x.mesh" --threads -2 --quiet
check "no output after refusals" [ ! -e "$work/x.mesh" ]

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
