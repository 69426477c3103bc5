#!/bin/sh
# `cagekit export-surfaces` end to end (issue 25, deliverable 4): a generated quad cube (closed) and
# an open 3 x 2 quad grid at --tolerance 1e-3, written as STEP through OpenCASCADE and read back
# (--check): face counts, closed shell / solid / validity, the read-back distance to the limit
# surface; the bad-input and usage conventions. Exit 77 (skipped) when this cagekit was built
# without OpenCASCADE (CAGEKIT_WITH_OCCT off).
# usage: check_cli_export_surfaces.sh CAGEKIT
set -u
cli="$1"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
failures=0; passed=0
pass() { passed=$((passed + 1)); echo "[ OK   ] $1"; }
fail() { failures=$((failures + 1)); echo "[ FAIL ] $1"; }

cat >"$tmp/cube.obj" <<'OBJ'
v 0 0 0
v 1 0 0
v 0 1 0
v 1 1 0
v 0 0 1
v 1 0 1
v 0 1 1
v 1 1 1
f 1 3 4 2
f 5 6 8 7
f 1 2 6 5
f 3 7 8 4
f 1 5 7 3
f 2 4 8 6
OBJ
# An open 3 x 2 grid of quads, gently curved.
{ for j in 0 1 2; do for i in 0 1 2 3; do echo "v $i $j 0.$((i * j))"; done; done
  for j in 0 1; do for i in 1 2 3; do a=$((j * 4 + i)); echo "f $a $((a + 1)) $((a + 5)) $((a + 4))"; done; done
} >"$tmp/grid.obj"

"$cli" export-surfaces "$tmp/cube.obj" "$tmp/cube.step" --tolerance 1e-3 --check >"$tmp/out" 2>"$tmp/err"
code=$?
if [ $code -eq 64 ] && grep -q "without OpenCASCADE" "$tmp/err"; then cat "$tmp/err"; echo "SKIP: built without OpenCASCADE"; exit 77; fi
if [ $code -eq 0 ]; then pass "cube: exit 0"; else cat "$tmp/err"; fail "cube: exit $code"; fi

# check_json FILE.json PYTHON-EXPRESSION-over-j NAME
check_json() {
  if /usr/bin/env python3 -c 'import json, sys
j = json.loads(open(sys.argv[1]).read())
sys.exit(0 if eval(sys.argv[2]) else 1)' "$1" "$2"; then pass "$3"; else cat "$1"; fail "$3"; fi
}
check_json "$tmp/out" 'j["surfaces"] == 6 and j["faces"] == 6 and j["ptex_faces"] == 6' "cube: 6 surfaces, 6 STEP faces"
check_json "$tmp/out" 'j["closed"] and j["solid"] and j["valid"] and j["free_edges"] == 0 and j["shells"] == 1' \
  "cube: one closed shell, a valid solid"
check_json "$tmp/out" 'j["over_tolerance"] == 0 and 0 < j["max_error_rel"] <= 1e-3 and j["max_normal_jump_deg"] < 2' \
  "cube: within 1e-3, normals agree within 2 deg"
check_json "$tmp/out" "j['bytes'] > 1000 and j['bytes'] == $(wc -c <"$tmp/cube.step")" "cube: bytes is the file's size"
check_json "$tmp/out" 'j["read_back"]["faces"] == 6 and j["read_back"]["solids"] == 1 and j["read_back"]["valid"]' \
  "cube: read back: 6 faces, one valid solid"
check_json "$tmp/out" 'j["read_back"]["points"] == 6 * 25 and j["read_back"]["max_distance_rel"] <= 1e-3' \
  "cube: read back: 150 limit points within 1e-3 of the diagonal"
if head -c 13 "$tmp/cube.step" | grep -q "ISO-10303-21"; then pass "cube: a STEP (ISO-10303-21) file"; else fail "cube: not STEP"; fi
check_json "$tmp/out" 'j["knot_removal_rel"] == 1e-4 and 0 < j["control_points"] <= j["control_points_before"] and 0 <= j["max_knot_removal_deviation_rel"] <= 1e-4' \
  "cube: knots removed within a tenth of --tolerance by default, the move measured"
mv "$tmp/out" "$tmp/cube.json"
"$cli" export-surfaces "$tmp/cube.obj" "$tmp/cube0.step" --tolerance 1e-3 --knot-removal 0 >"$tmp/out" 2>"$tmp/err"
check_json "$tmp/out" 'j["control_points"] == j["control_points_before"] and j["max_knot_removal_deviation_rel"] == 0' \
  "cube: --knot-removal 0 keeps every control point"
check_json "$tmp/cube.json" "j['control_points_before'] == $(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["control_points_before"])' "$tmp/out")" \
  "cube: the same surfaces before removal either way"

if "$cli" export-surfaces "$tmp/grid.obj" "$tmp/grid.step" --tolerance 1e-3 --check --schema AP203 >"$tmp/grid.json" 2>"$tmp/err"
then pass "grid: exit 0"; else cat "$tmp/err"; fail "grid: exit $?"; fi
check_json "$tmp/grid.json" 'j["faces"] == 6 and j["free_edges"] == 10 and j["shells"] == 1' "grid: 6 faces, 10 free edges"
check_json "$tmp/grid.json" 'not j["closed"] and not j["solid"] and j["valid"]' "grid: an open valid shell, no solid"
check_json "$tmp/grid.json" 'j["read_back"]["faces"] == 6 and j["read_back"]["solids"] == 0 and j["read_back"]["max_distance_rel"] <= 1e-3' \
  "grid: read back: 6 faces, no solid, within 1e-3"
if grep -q "FILE_SCHEMA(('CONFIG_CONTROL_DESIGN'))" "$tmp/grid.step"; then pass "grid: --schema AP203 written"; else fail "grid: schema"; fi

# Conventions: bad input exit 2 with one line, usage exit 64, no file written.
"$cli" export-surfaces "$tmp/missing.obj" "$tmp/m.step" >"$tmp/out" 2>"$tmp/err"; code=$?
if [ $code -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q "missing.obj" "$tmp/err" && [ ! -e "$tmp/m.step" ]
then pass "missing cage: exit 2, one line naming it"; else cat "$tmp/err"; fail "missing cage: exit $code"; fi
"$cli" export-surfaces "$tmp/cube.obj" "$tmp/no/such/dir/c.step" --quiet >"$tmp/out" 2>"$tmp/err"; code=$?
if [ $code -eq 2 ] && grep -q "c.step" "$tmp/err"; then pass "unwritable output: exit 2"; else cat "$tmp/err"; fail "unwritable output: exit $code"; fi
for bad in "--per block" "--tolerance 0" "--tolerance 2" "--max-level 8" "--schema AP242" "--knot-removal -2"; do
  # shellcheck disable=SC2086
  "$cli" export-surfaces "$tmp/cube.obj" "$tmp/b.step" $bad >"$tmp/out" 2>"$tmp/err"; code=$?
  if [ $code -eq 64 ] && [ ! -e "$tmp/b.step" ]; then pass "$bad: exit 64"; else cat "$tmp/err"; fail "$bad: exit $code"; fi
done

echo "$passed passed, $failures failed"
[ $failures -eq 0 ]
