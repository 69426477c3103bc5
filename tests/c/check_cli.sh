#!/bin/sh
# End-to-end checks of the `cagekit` CLI and the C host sample: demo output, info --json keys,
# conversions that keep cage tags, fandisk through Draco, simplification, fit and pipeline, and
# the bad-input convention
# (one line on stderr naming the file, exit code 2, no output file left behind).
# usage: check_cli.sh CAGEKIT C_HOST SHARED_MESHES_DIR
set -u
cli="$1"; host="$2"; meshes="$3"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
failures=0; passed=0
pass() { passed=$((passed + 1)); echo "[ OK   ] $1"; }
fail() { failures=$((failures + 1)); echo "[ FAIL ] $1"; }
# release_only WHAT: true (and says so) in sanitizer builds (CAGEKIT_CHECK_CLI_SANITIZED set), where
# the heavy runs WHAT take minutes each; the Release pass runs them.
release_only() {
  [ -n "${CAGEKIT_CHECK_CLI_SANITIZED:-}" ] || return 1
  echo "[ SKIP ] $1: Release only (sanitizer build: minutes each there)"
}
json() { /usr/bin/env python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2], {'d': d}))" "$@"; }

# 1. demo
if "$cli" demo "$tmp/demo" --quiet >"$tmp/demo.out" 2>&1 &&
   for f in scan.obj scan.ply scan.drc cage.obj cage.drc cage_level3.obj scan_level1_limit.obj summary.json \
            cage_fitted.obj cage_fitted_limit.obj pipeline.json; do
     [ -s "$tmp/demo/$f" ] || exit 1; done; then pass "demo writes its outputs"; else cat "$tmp/demo.out"; fail "demo"; fi

if [ "$(json "$tmp/demo/summary.json" "d['cage']['quads'] == 6 and d['cage']['creases'] == 12 and d['cage']['triangles'] == 0 and d['cage']['level3_limit_hausdorff_rel'] < 1e-3 and d['scan']['valid']")" = True ]
then pass "demo: the scan of a block simplifies to a 6-quad cage with 12 creases whose limit is within 0.1% of the scan"; else cat "$tmp/demo/summary.json"; fail "demo pipeline"; fi

# 1a. demo's overview.png (scan | cage over its limit | error map), or a note where it cannot draw
png_check="$(dirname "$0")/png_check.py"
overview=$(json "$tmp/demo/summary.json" "d['overview']")
if [ "$overview" = None ]; then
  if [ ! -e "$tmp/demo/overview.png" ] && grep -q "overview.png  *not written: " "$tmp/demo.out"
  then pass "demo: no overview.png here (no headless EGL), one line says why"; else fail "demo: overview note"; fi
elif [ "$overview" = overview.png ] &&
     /usr/bin/env python3 "$png_check" "$tmp/demo/overview.png" --size 960x400 --min-share 0.15 --max-share 0.8 \
       --color 230,38,140,50 --color 253,231,37,5
then pass "demo: overview.png 960 x 400 with the cage's creases and the error map's legend"; else fail "demo: overview.png"; fi

# 1b. progress into a file (not a terminal): one plain line per stage, no carriage returns
if "$cli" demo "$tmp/demo-log" >/dev/null 2>"$tmp/demo.err" && grep -q '^cagekit: stage: simplify$' "$tmp/demo.err" &&
   ! grep -q "$(printf '\r')" "$tmp/demo.err"
then pass "progress written to a file is one line per stage, without carriage returns"; else cat -A "$tmp/demo.err" | head -20; fail "progress into a file"; fi

# 2. info --json on the demo scan
"$cli" info "$tmp/demo/scan.obj" --json >"$tmp/info.json" 2>/dev/null
if [ "$(json "$tmp/info.json" "all(k in d for k in 'vertices faces quads triangles boundary_loops genus manifold bbox_diagonal creases corners'.split()) and d['genus'] == 0 and d['boundary_loops'] == 0 and d['manifold'] and d['triangles'] == d['faces']")" = True ]
then pass "info --json keys and values"; else cat "$tmp/info.json"; fail "info --json"; fi

# 2b. a path with control characters, quotes and a backslash stays a valid JSON string
odd="$tmp/$(printf 'odd\t"name\\\001\nx').obj"
cp "$tmp/demo/scan.obj" "$odd"
if "$cli" info "$odd" --json >"$tmp/odd.json" 2>/dev/null &&
   /usr/bin/env python3 -c "import json,sys; d=json.load(open(sys.argv[1])); sys.exit(d['file'] != sys.argv[2])" "$tmp/odd.json" "$odd"
then pass "info --json escapes a path with control characters"; else cat -A "$tmp/odd.json"; fail "info --json escaping"; fi

# 3. a crease-tagged quad cube survives OBJ -> DRC -> OBJ with its 6 quads and tags
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
t crease 2/1/0 0 1 10
t crease 2/1/0 2 3 10
t crease 2/1/0 4 5 10
t crease 2/1/0 6 7 10
t crease 2/1/0 0 2 10
t crease 2/1/0 1 3 10
t crease 2/1/0 4 6 10
t crease 2/1/0 5 7 10
t crease 2/1/0 0 4 10
t crease 2/1/0 1 5 10
t crease 2/1/0 2 6 10
t crease 2/1/0 3 7 2.5
t corner 1/1/0 0 10
t corner 1/1/0 7 3
OBJ
if "$cli" convert "$tmp/cube.obj" "$tmp/cube.drc" --quiet && "$cli" convert "$tmp/cube.drc" "$tmp/cube2.obj" --quiet &&
   "$cli" info "$tmp/cube2.obj" --json >"$tmp/cube2.json" &&
   [ "$(json "$tmp/cube2.json" "d['quads'] == 6 and d['faces'] == 6 and d['creases'] == 12 and d['corners'] == 2")" = True ] &&
   [ "$(grep -c '^t crease' "$tmp/cube2.obj")" -ge 1 ] && grep -q '^t crease.* 2.5$' "$tmp/cube2.obj" &&
   grep -q '^t corner.* 3$' "$tmp/cube2.obj"
then pass "creased quad cube OBJ -> DRC -> OBJ keeps 6 quads and its tags"; else cat "$tmp/cube2.json" "$tmp/cube2.obj"; fail "cube tags through Draco"; fi

# 4. subdivide the cube with its creases
if "$cli" subdivide "$tmp/cube.obj" "$tmp/cube3.obj" --levels 3 --quiet && "$cli" info "$tmp/cube3.obj" --json >"$tmp/cube3.json" &&
   [ "$(json "$tmp/cube3.json" "d['quads'] == 384 and d['creases'] >= 88 and d['genus'] == 0")" = True ]
then pass "subdivide keeps creases"; else cat "$tmp/cube3.json"; fail "subdivide cube"; fi

# 5. fandisk through Draco at 14 bits, and subdivided to level 2
fandisk="$meshes/fandisk.obj"
if [ -f "$fandisk" ]; then
  if "$cli" convert "$fandisk" "$tmp/fandisk.drc" --quiet && "$cli" convert "$tmp/fandisk.drc" "$tmp/fandisk2.obj" --quiet &&
     /usr/bin/env python3 - "$fandisk" "$tmp/fandisk.drc" "$tmp/fandisk2.obj" <<'PY'
import os, sys, math
def load(p):
    vs = [tuple(map(float, l.split()[1:4])) for l in open(p) if l.startswith('v ')]
    fs = [l.split()[1:] for l in open(p) if l.startswith('f ')]
    return vs, fs
a, fa = load(sys.argv[1]); b, fb = load(sys.argv[3])
assert len(a) == len(b) and len(fa) == len(fb), (len(a), len(b), len(fa), len(fb))
lo = [min(v[k] for v in a) for k in range(3)]; hi = [max(v[k] for v in a) for k in range(3)]
diag = math.dist(lo, hi)
err = max(math.dist(p, q) for p, q in zip(a, b)) / diag
obj, drc = os.path.getsize(sys.argv[1]), os.path.getsize(sys.argv[2])
print(f"fandisk: max error {err:.3g} of diagonal, OBJ {obj} B, DRC {drc} B ({obj/drc:.1f}x)")
assert err <= 1e-4, err
assert drc * 10 <= obj, (drc, obj)
PY
  then pass "fandisk OBJ -> DRC -> OBJ within 1e-4 of the diagonal, DRC 10x smaller"; else fail "fandisk Draco"; fi
  if "$cli" subdivide "$fandisk" "$tmp/fandisk_l2.obj" --levels 2 --quiet && "$cli" info "$tmp/fandisk_l2.obj" --json >"$tmp/fl2.json" &&
     [ "$(json "$tmp/fl2.json" "d['quads'] == 12946 * 12")" = True ]
  then pass "fandisk subdivided to level 2"; else fail "fandisk subdivide"; fi
else
  echo "[ SKIP ] fandisk checks: $fandisk not present"
fi

# 6. bad input: one line naming the file, exit code 2, no output file
expect_bad() {  # name input-file command...
  name="$1"; shift
  rm -f "$tmp/out.obj" "$tmp/out.drc"
  "$@" >"$tmp/bad.out" 2>"$tmp/bad.err"; code=$?
  lines=$(wc -l <"$tmp/bad.err")
  if [ "$code" -eq 2 ] && [ "$lines" -eq 1 ] && [ ! -e "$tmp/out.obj" ] && [ ! -e "$tmp/out.drc" ] &&
     ! ls "$tmp" | grep -q '\.tmp'; then pass "bad input: $name"; else
     echo "exit $code, $lines lines:"; cat "$tmp/bad.err"; fail "bad input: $name"; fi
}
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n' >"$tmp/badindex.obj"
expect_bad "index out of range" "$cli" convert "$tmp/badindex.obj" "$tmp/out.drc" --quiet
grep -q 'badindex.obj:4' "$tmp/bad.err" && pass "message names file and line" || { cat "$tmp/bad.err"; fail "message names file and line"; }
printf 'v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$tmp/nan.obj"
expect_bad "NaN coordinate" "$cli" subdivide "$tmp/nan.obj" "$tmp/out.obj" --levels 1 --quiet
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n' >"$tmp/huge.ply"
expect_bad "hostile PLY count" "$cli" convert "$tmp/huge.ply" "$tmp/out.obj" --quiet
{ head -c 80 /dev/zero; printf '\377\377\377\377'; } >"$tmp/huge.stl"
expect_bad "hostile binary STL count" "$cli" convert "$tmp/huge.stl" "$tmp/out.obj" --quiet
grep -q 'huge.stl: byte 80: .*4294967295' "$tmp/bad.err" && pass "STL count message names file, byte and count" ||
  { cat "$tmp/bad.err"; fail "STL count message"; }
head -c 200 "$tmp/demo/scan.drc" >"$tmp/truncated.drc"
expect_bad "truncated Draco" "$cli" convert "$tmp/truncated.drc" "$tmp/out.obj" --quiet
expect_bad "missing file" "$cli" info "$tmp/does-not-exist.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 2 1 3\nf 1 2 3\n' >"$tmp/nonmanifold.obj"
expect_bad "invalid cage for subdivide" "$cli" subdivide "$tmp/nonmanifold.obj" "$tmp/out.obj" --levels 1 --quiet

# 6a. STL: an ascii tetrahedron soup is read welded; writing STL is refused up front (usage error)
{ echo "solid tet"
  for t in "0 0 0|0 1 0|1 0 0" "0 0 0|1 0 0|0 0 1" "0 0 0|0 0 1|0 1 0" "1 0 0|0 1 0|0 0 1"; do
    echo " facet normal 0 0 0"; echo "  outer loop"
    echo "$t" | tr '|' '\n' | sed 's/^/   vertex /'
    echo "  endloop"; echo " endfacet"
  done
  echo "endsolid tet"; } >"$tmp/tet.stl"
if "$cli" info "$tmp/tet.stl" --json >"$tmp/tet.json" 2>"$tmp/tet.err" &&
   [ "$(json "$tmp/tet.json" "d['vertices'] == 4 and d['faces'] == 4 and d['manifold'] and d['boundary_loops'] == 0 and d['genus'] == 0")" = True ] &&
   "$cli" convert "$tmp/tet.stl" "$tmp/tet.obj" --quiet && [ "$(grep -c '^v ' "$tmp/tet.obj")" = 4 ]
then pass "ascii STL reads as a welded closed tetrahedron"; else cat "$tmp/tet.json" "$tmp/tet.err"; fail "ascii STL"; fi
"$cli" convert "$tmp/tet.obj" "$tmp/tet-out.stl" --quiet 2>"$tmp/stl.err"; code=$?
if [ "$code" -eq 64 ] && grep -q 'tet-out.stl: STL: writing is not supported' "$tmp/stl.err" && [ ! -e "$tmp/tet-out.stl" ]
then pass "convert to .stl: clean 'STL: writing is not supported'"; else echo "exit $code"; cat "$tmp/stl.err"; fail "convert to .stl"; fi

# 8. structure-preserving simplification to a cage with creases
rocker="$meshes/rocker-arm.obj"
if [ -f "$rocker" ]; then
  if "$cli" simplify "$rocker" "$tmp/rocker6.obj" --faces 6 --cage --json --quiet --clusters "$tmp/rocker-clusters.ply" >"$tmp/rocker.json" &&
     [ "$(json "$tmp/rocker.json" "d['invalid_faces'] == 0 and d['non_manifold_edges'] == 0 and d['polygons'] <= 12 and d['faces'] == d['quads'] + d['triangles'] + d['pentagons'] and d['other_polygons'] == 0 and all(k in d for k in 'polygons faces vertices quads triangles pentagons invalid_faces creases l2_error l21_error hausdorff_rel hausdorff_sym_rel seconds'.split())")" = True ] &&
     [ "$(grep -c '^element face 20088' "$tmp/rocker-clusters.ply")" = 1 ] && "$cli" info "$tmp/rocker6.obj" --json >"$tmp/r6.json" &&
     [ "$(json "$tmp/r6.json" "d['valid'] and d['genus'] == 1")" = True ]
  then pass "simplify rocker-arm to a coarse cage (valid, genus kept, clusters file)"; else cat "$tmp/rocker.json" "$tmp/r6.json"; fail "simplify rocker-arm"; fi
  # The same level with its contours refined (VSA's rule: 5 mean edge lengths ~ 0.05 of the diagonal):
  # same polygon count, more vertices, a smaller distance to the input.
  if "$cli" simplify "$rocker" "$tmp/rocker6p.obj" --faces 6 --json --quiet >"$tmp/rocker6p.json" &&
     "$cli" simplify "$rocker" "$tmp/rocker6r.obj" --faces 6 --contour-tolerance 0.05 --json --quiet >"$tmp/rocker6r.json" &&
     [ "$(python3 -c "import json,sys; a=json.load(open(sys.argv[1])); b=json.load(open(sys.argv[2])); print(a['polygons'] == b['polygons'] and b['vertices'] > a['vertices'] and b['hausdorff_rel'] < 0.5 * a['hausdorff_rel'] and b['invalid_faces'] == 0)" "$tmp/rocker6p.json" "$tmp/rocker6r.json")" = True ]
  then pass "simplify --contour-tolerance: same polygons, more vertices, Hausdorff less than half"; else cat "$tmp/rocker6p.json" "$tmp/rocker6r.json"; fail "simplify --contour-tolerance"; fi
else
  echo "[ SKIP ] simplify checks: $rocker not present"
fi
"$cli" simplify "$tmp/badindex.obj" "$tmp/out.obj" --faces 10 --cage --contour-tolerance 0.01 --quiet 2>"$tmp/usage.err"; code=$?
if [ "$code" -eq 64 ] && grep -q "does not apply with --cage" "$tmp/usage.err" && [ ! -e "$tmp/out.obj" ]
then pass "usage: simplify --contour-tolerance with --cage is refused (exit 64)"; else cat "$tmp/usage.err"; fail "simplify --contour-tolerance with --cage"; fi
expect_bad "simplify of a corrupt file" "$cli" simplify "$tmp/badindex.obj" "$tmp/out.obj" --faces 10 --quiet

# 8b. anisotropic remeshing (thesis ch. 5): report keys, bounded valence, fandisk creases, pipeline
fandisk="$meshes/fandisk.obj"
if [ -f "$fandisk" ]; then
  remesh_keys="faces vertices quads_pct valence4_vertices_pct max_face_valence max_vertex_valence creases hausdorff_rel hausdorff_sym_rel min_scaled_jacobian regions seconds mean_alignment_deg"
  if "$cli" remesh "$fandisk" "$tmp/fan-aniso.obj" --method anisotropic --tolerance 0.002 --json --quiet >"$tmp/fan-aniso.json" &&
     [ "$(json "$tmp/fan-aniso.json" "all(k in d for k in '$remesh_keys'.split()) and d['max_face_valence'] <= 5 and d['creases'] > 100 and d['quads_pct'] > 50 and d['min_scaled_jacobian'] >= 0 and d['hausdorff_sym_rel'] < 0.02")" = True ] &&
     "$cli" info "$tmp/fan-aniso.obj" --json >"$tmp/fan-aniso-info.json" && [ "$(json "$tmp/fan-aniso-info.json" "d['valid'] and d['genus'] == 0")" = True ]
  then pass "remesh --method anisotropic: fandisk quad-dominant, creases kept, valid, genus 0"; else cat "$tmp/fan-aniso.json"; fail "remesh anisotropic"; fi
  if ! release_only "fandisk pipeline --method anisotropic"; then
    if "$cli" pipeline "$fandisk" "$tmp/fan-pipe" --method anisotropic --tolerance 0.002 --passes 2 --quiet &&
       [ "$(json "$tmp/fan-pipe/report.json" "d['remesh']['method'] == 'anisotropic' and d['limit']['error']['hausdorff_sym_rel'] < 0.02")" = True ]
    then pass "pipeline --method anisotropic: remesh -> fit -> limit within 2% of the diagonal"; else cat "$tmp/fan-pipe/report.json"; fail "pipeline anisotropic"; fi
  fi
  # 8c. two-step quad-dominant remeshing (thesis ch. 6), Table 6.1 settings for fandisk
  if "$cli" remesh "$fandisk" "$tmp/fan-quad.obj" --method quad --edge-length 0.10 --regions 30 --weights 500,500,500 --json --quiet >"$tmp/fan-quad.json" &&
     [ "$(json "$tmp/fan-quad.json" "all(k in d for k in '$remesh_keys'.split()) and d['method'] == 'quad' and d['regions'] == 30 and d['creases'] > 50 and d['quads_pct'] > 80 and d['max_face_valence'] <= 6 and d['hausdorff_sym_rel'] < 0.03")" = True ] &&
     "$cli" info "$tmp/fan-quad.obj" --json >"$tmp/fan-quad-info.json" && [ "$(json "$tmp/fan-quad-info.json" "d['valid'] and d['genus'] == 0 and d['boundary_edges'] == 0")" = True ]
  then pass "remesh --method quad: fandisk quad-dominant, creases on sharp region boundaries, valid, closed, genus 0"; else cat "$tmp/fan-quad.json"; fail "remesh quad"; fi
  if ! release_only "fandisk remesh --method quad --refinement-passes 0 and pipeline --method quad"; then
    if "$cli" remesh "$fandisk" "$tmp/fan-quad0.obj" --method quad --edge-length 0.10 --regions 30 --weights 500,500,500 --refinement-passes 0 --json --quiet >"$tmp/fan-quad0.json" &&
       [ "$(json "$tmp/fan-quad0.json" "d['refinement_passes'] == 0 and d['regions'] == 30 and d['quads_pct'] > 80")" = True ]
    then pass "remesh --method quad --refinement-passes 0: fandisk quad-dominant without the refinement"; else cat "$tmp/fan-quad0.json"; fail "remesh quad without refinement"; fi
    if "$cli" pipeline "$fandisk" "$tmp/fan-pipe-quad" --method quad --edge-length 0.10 --passes 2 --quiet &&
       [ "$(json "$tmp/fan-pipe-quad/report.json" "d['remesh']['method'] == 'quad' and d['limit']['error']['hausdorff_sym_rel'] < 0.02")" = True ]
    then pass "pipeline --method quad: remesh -> fit -> limit within 2% of the diagonal"; else cat "$tmp/fan-pipe-quad/report.json"; fail "pipeline quad"; fi
  fi
else
  echo "[ SKIP ] remesh checks: $fandisk not present"
fi
expect_bad "remesh --method quad with two weights" "$cli" remesh "$tmp/cube.obj" "$tmp/out.obj" --method quad --weights 1,2 --quiet
expect_bad "remesh --method quad with 17 refinement passes" "$cli" remesh "$tmp/cube.obj" "$tmp/out.obj" --method quad --refinement-passes 17 --quiet
expect_bad "remesh --method quad with a zero edge length" "$cli" remesh "$tmp/cube.obj" "$tmp/out.obj" --method quad --edge-length 0 --quiet
# More regions than triangles: the count is capped at the triangle count and reported, not refused.
if "$cli" remesh "$tmp/cube.obj" "$tmp/capped.obj" --method quad --regions 100000 --json --quiet >"$tmp/capped.json" &&
   grep -q '"regions": ' "$tmp/capped.json" && "$cli" info "$tmp/capped.obj" >/dev/null; then
  pass "remesh --method quad with more regions than triangles: capped, valid cage"
else
  cat "$tmp/capped.json"; fail "remesh --method quad with more regions than triangles"
fi
"$cli" remesh "$tmp/cube.obj" "$tmp/out.obj" --quiet 2>"$tmp/usage.err"; code=$?
if [ "$code" -eq 64 ] && grep -q "method is required" "$tmp/usage.err"; then pass "usage: remesh without --method (exit 64)"; else cat "$tmp/usage.err"; fail "remesh without --method"; fi
expect_bad "remesh with an unknown method" "$cli" remesh "$tmp/cube.obj" "$tmp/out.obj" --method quadx --quiet
expect_bad "remesh of a non-manifold mesh" "$cli" remesh "$tmp/nonmanifold.obj" "$tmp/out.obj" --method anisotropic --quiet

# 9. fitting (thesis ch. 7): a cage from the demo scan, and the creased unit cube, fitted to the scan
fit_keys="passes l2 rms_rel max_rel mean_rel max_rel_interior seconds per_pass stopped_by_tolerance unconverged_projections"
pass_keys="l2 rms_rel max_rel mean_rel max_rel_interior seconds unconverged_projections"
fit_ok="all(k in F for k in '$fit_keys'.split()) and all(k in p for p in F['per_pass'] for k in '$pass_keys'.split()) and len(F['per_pass']) == F['passes'] + 1 and F['per_pass'][-1]['max_rel'] < F['per_pass'][0]['max_rel'] and all(b['l2'] <= a['l2'] for a, b in zip(F['per_pass'], F['per_pass'][1:])) and F['max_rel'] == F['per_pass'][F['best_pass']]['max_rel'] and F['best_pass'] <= F['passes']"
if "$cli" simplify "$tmp/demo/scan.obj" "$tmp/scan6.obj" --faces 6 --cage --quiet &&
   "$cli" fit "$tmp/demo/scan.obj" "$tmp/scan6.obj" "$tmp/fit6.obj" --passes 3 --json --quiet >"$tmp/fit6.json" &&
   [ "$(json "$tmp/fit6.json" "[F := d, $fit_ok][1] and d['passes'] >= 1")" = True ] &&
   "$cli" info "$tmp/fit6.obj" --json >"$tmp/fit6info.json" &&
   [ "$(json "$tmp/fit6info.json" "d['quads'] == 6 and d['creases'] == 12")" = True ]
then pass "fit: a creased 6-quad cage to the demo scan (JSON keys, max_rel decreases, tags kept)"; else cat "$tmp/fit6.json" "$tmp/fit6info.json"; fail "fit cage to demo scan"; fi
if "$cli" simplify "$tmp/demo/scan.obj" "$tmp/scan6s.obj" --faces 6 --cage --creases cluster-angle --input-crease-angle 30 --json --quiet >"$tmp/scan6s.json" &&
   [ "$(json "$tmp/scan6s.json" "d['creases'] == 12")" = True ] &&
   "$cli" simplify "$tmp/demo/scan.obj" "$tmp/scan6n.obj" --faces 6 --cage --creases cluster-angle --input-crease-angle 120 --json --quiet >"$tmp/scan6n.json" &&
   [ "$(json "$tmp/scan6n.json" "d['creases'] == 0")" = True ]
then pass "simplify --input-crease-angle: the block's 90-degree edges stay creases at 30, not at 120"; else cat "$tmp/scan6s.json" "$tmp/scan6n.json"; fail "simplify --input-crease-angle"; fi
if "$cli" simplify "$tmp/demo/scan.obj" "$tmp/scan6d.obj" --faces 6 --cage --json --quiet >"$tmp/scan6d.json" &&
   [ "$(json "$tmp/scan6d.json" "d['creases'] == 12")" = True ] &&
   "$cli" simplify "$tmp/demo/scan.obj" "$tmp/scan6f.obj" --faces 6 --cage --feature-angle 95 --json --quiet >"$tmp/scan6f.json" &&
   [ "$(json "$tmp/scan6f.json" "d['creases'] == 0")" = True ] &&
   { "$cli" simplify "$tmp/demo/scan.obj" "$tmp/scan6x.obj" --faces 6 --cage --creases sharp 2>"$tmp/scan6x.err"; [ $? -eq 2 ]; } &&
   grep -q "sharp-input" "$tmp/scan6x.err"
then pass "simplify creases where the scan is sharp by default (--feature-angle 95: none); a bad --creases is exit 2"; else cat "$tmp/scan6d.json" "$tmp/scan6f.json" "$tmp/scan6x.err"; fail "simplify --creases / --feature-angle"; fi
if "$cli" fit "$tmp/demo/scan.obj" "$tmp/cube.obj" "$tmp/fitcube.drc" --passes 4 --tolerance 0 --projection linear --json --quiet >"$tmp/fitcube.json" &&
   [ "$(json "$tmp/fitcube.json" "[F := d, $fit_ok][1] and d['passes'] >= 2 and d['max_rel'] < 0.5 * d['per_pass'][0]['max_rel']")" = True ] &&
   [ -s "$tmp/fitcube.drc" ]
then pass "fit: the unit cube to the 4 x 2.5 x 1.5 block (piecewise-linear projection, Draco output)"; else cat "$tmp/fitcube.json"; fail "fit cube to block"; fi
if "$cli" pipeline "$tmp/demo/scan.obj" "$tmp/pipe/out" --faces 30 --passes 3 --json --quiet >"$tmp/pipe.json" &&
   [ -s "$tmp/pipe/out/cage.obj" ] && [ -s "$tmp/pipe/out/limit.obj" ] && [ -s "$tmp/pipe/out/report.json" ] &&
   [ "$(json "$tmp/pipe.json" "[F := d['fit'], $fit_ok][1] and all(k in d['simplify'] for k in 'level polygons quads triangles creases error seconds'.split()) and d['simplify']['polygons'] <= 30 and d['limit']['error']['hausdorff_sym_rel'] < 2e-3")" = True ] &&
   [ "$(json "$tmp/pipe/out/report.json" "d['fit']['passes'] >= 1 and d['quality']['two_sided_refit'] in (True, False) and (not d['quality']['two_sided_refit'] or d['quality']['one_sided_fit_max_rel'] * 0.95 > d['limit']['error']['hausdorff_sym_rel'])")" = True ] &&
   grep -q '^t crease' "$tmp/pipe/out/cage.obj"
then pass "pipeline: simplify -> creased cage -> fit -> limit (OUTDIR created, report.json, JSON keys, error decreases)"; else cat "$tmp/pipe.json"; fail "pipeline"; fi
if [ "$(json "$tmp/demo/summary.json" "d['fit']['per_pass'][-1]['max_rel'] <= d['fit']['per_pass'][0]['max_rel'] and d['fitted_limit']['hausdorff_sym_rel'] < 1e-3")" = True ] &&
   [ -s "$tmp/demo/cage_fitted.obj" ] && [ -s "$tmp/demo/cage_fitted_limit.obj" ]
then pass "demo runs the pipeline and reports the fit"; else cat "$tmp/demo/summary.json"; fail "demo fit"; fi
head -c 3000 "$tmp/demo/scan.drc" >"$tmp/garbage.obj"
expect_bad "fit: missing scan" "$cli" fit "$tmp/does-not-exist.obj" "$tmp/cube.obj" "$tmp/out.obj" --quiet
expect_bad "fit: missing cage" "$cli" fit "$tmp/demo/scan.obj" "$tmp/does-not-exist.obj" "$tmp/out.obj" --quiet
expect_bad "fit: corrupt scan" "$cli" fit "$tmp/badindex.obj" "$tmp/cube.obj" "$tmp/out.obj" --quiet
expect_bad "fit: corrupt cage" "$cli" fit "$tmp/demo/scan.obj" "$tmp/badindex.obj" "$tmp/out.obj" --quiet
expect_bad "fit: binary garbage as the cage" "$cli" fit "$tmp/cube.obj" "$tmp/garbage.obj" "$tmp/out.obj" --quiet
expect_bad "fit: binary garbage as the scan" "$cli" fit "$tmp/garbage.obj" "$tmp/cube.obj" "$tmp/out.obj" --quiet
expect_bad "fit: a non-manifold mesh as the cage" "$cli" fit "$tmp/cube.obj" "$tmp/nonmanifold.obj" "$tmp/out.obj" --quiet
expect_bad "fit: NaN in the scan" "$cli" fit "$tmp/nan.obj" "$tmp/cube.obj" "$tmp/out.obj" --quiet
expect_bad "fit: --passes -1" "$cli" fit "$tmp/demo/scan.obj" "$tmp/cube.obj" "$tmp/out.obj" --passes -1 --quiet
expect_bad "fit: --tolerance nan" "$cli" fit "$tmp/demo/scan.obj" "$tmp/cube.obj" "$tmp/out.obj" --tolerance nan --quiet
expect_bad "fit: --projection bogus" "$cli" fit "$tmp/demo/scan.obj" "$tmp/cube.obj" "$tmp/out.obj" --projection bogus --quiet
expect_bad "pipeline: missing scan" "$cli" pipeline "$tmp/does-not-exist.obj" "$tmp/pipe2" --faces 6 --quiet
expect_bad "pipeline: corrupt scan" "$cli" pipeline "$tmp/badindex.obj" "$tmp/pipe2" --faces 6 --quiet
expect_bad "pipeline --no-repair: invalid scan" "$cli" pipeline "$tmp/nonmanifold.obj" "$tmp/pipe2" --faces 6 --no-repair --quiet
# Conditioning (on by default): duplicate faces dropped, the orientation made consistent, the
# 2 triangles left are their own cage (fewer faces than asked for), reported in report.json.
if "$cli" pipeline "$tmp/nonmanifold.obj" "$tmp/pipe-nm" --faces 6 --quiet &&
   [ "$(json "$tmp/pipe-nm/report.json" "d['conditioning']['input_faces'] == 4 and d['conditioning']['faces'] == 2 and d['conditioning']['dropped_duplicate_faces'] == 2 and d['conditioning']['flipped_faces'] == 1 and d['input_is_cage'] and d['quality']['good']")" = True ]
then pass "pipeline conditions a non-manifold scan (duplicates dropped, orientation fixed) and reports it"; else cat "$tmp/pipe-nm/report.json"; fail "pipeline conditioning"; fi
expect_bad "pipeline: --components other" "$cli" pipeline "$tmp/demo/scan.obj" "$tmp/pipe2" --faces 6 --components some --quiet
expect_bad "pipeline: NaN in the scan" "$cli" pipeline "$tmp/nan.obj" "$tmp/pipe2" --faces 6 --quiet
expect_bad "pipeline: --passes -1" "$cli" pipeline "$tmp/demo/scan.obj" "$tmp/pipe2" --faces 6 --passes -1 --quiet
expect_bad "pipeline: --two-sided-refit -1" "$cli" pipeline "$tmp/demo/scan.obj" "$tmp/pipe2" --faces 6 --two-sided-refit -1 --quiet
if "$cli" pipeline "$tmp/demo/scan.obj" "$tmp/pipe-one" --faces 30 --two-sided-refit 0 --quiet &&
   [ "$(json "$tmp/pipe-one/report.json" "d['quality']['two_sided_refit'] is False and 'one_sided_fit_max_rel' not in d['quality']")" = True ]
then pass "pipeline --two-sided-refit 0: the one-sided fit is returned"; else cat "$tmp/pipe-one/report.json"; fail "pipeline --two-sided-refit 0"; fi
expect_bad "pipeline: --crease-feature-reach 2" "$cli" pipeline "$tmp/demo/scan.obj" "$tmp/pipe2" --faces 6 --crease-feature-reach 2 --quiet
expect_bad "fit: --crease-feature-reach -1" "$cli" fit "$tmp/demo/scan.obj" "$tmp/demo/scan.obj" "$tmp/fit-bad.obj" --crease-feature-reach -1 --quiet
expect_bad "pipeline: --method other" "$cli" pipeline "$tmp/demo/scan.obj" "$tmp/pipe2" --faces 6 --method qem --quiet
expect_bad "pipeline: OUTDIR under a file" "$cli" pipeline "$tmp/demo/scan.obj" "$tmp/cube.obj/sub" --faces 6 --quiet

# 6b. multiresolution editing: deform the demo scan over its fitted cage with 3 vertices moved
python3 - "$tmp/pipe/out/cage.obj" "$tmp/edited.obj" <<'PY'
import sys
lines = open(sys.argv[1]).read().splitlines(); out = []; k = 0
for l in lines:
    if l.startswith('v '):
        p = l.split()
        if k in (0, 3, 5): p[3] = str(float(p[3]) + 0.05)
        l = ' '.join(p); k += 1
    out.append(l)
open(sys.argv[2], 'w').write('\n'.join(out) + '\n')
PY
if "$cli" deform "$tmp/demo/scan.obj" "$tmp/pipe/out/cage.obj" "$tmp/pipe/out/cage.obj" "$tmp/same.obj" --local-frame --json --quiet >"$tmp/deform0.json" &&
   python3 - "$tmp/demo/scan.obj" "$tmp/same.obj" <<'PY'
import sys
def verts(p): return [tuple(map(float, l.split()[1:4])) for l in open(p) if l.startswith('v ')]
a, b = verts(sys.argv[1]), verts(sys.argv[2])
assert len(a) == len(b) and len(a) > 100
assert max(max(abs(x - y) for x, y in zip(p, q)) for p, q in zip(a, b)) < 1e-6
PY
then pass "deform: the unedited cage gives the scan back (local-frame mode)"; else cat "$tmp/deform0.json"; fail "deform identity"; fi
if "$cli" deform "$tmp/demo/scan.obj" "$tmp/pipe/out/cage.obj" "$tmp/edited.obj" "$tmp/deformed.ply" --json --quiet >"$tmp/deform.json" &&
   [ -s "$tmp/deformed.ply" ] && [ "$(json "$tmp/deform.json" 'd["max_control_move_rel"] > 0 and d["vertices"] > 100')" = True ]
then pass "deform: edited cage -> deformed scan (PLY), JSON report"; else cat "$tmp/deform.json"; fail "deform"; fi
if "$cli" bench-deform "$tmp/demo/scan.obj" "$tmp/pipe/out/cage.obj" --frames 20 --moved 3 --json --quiet >"$tmp/bench.json" &&
   [ "$(json "$tmp/bench.json" 'all(k in d for k in ("vertices","triangles","moved","cpu_fps","cpu_fps_f32","cpu_incremental_fps","gpu_fps","gpu_renderer","bytes_per_vertex")) and d["cpu_fps"] > 0 and d["cpu_fps_f32"] > 0 and (d["gpu_fps"] is None) == (d["gpu_renderer"] is None) and (d["gpu_fps"] is None or d["gpu_fps"] > 0)')" = True ]
then pass "bench-deform: JSON keys, CPU frame rates"; else cat "$tmp/bench.json"; fail "bench-deform"; fi
expect_bad "deform: cage with other vertex count" "$cli" deform "$tmp/demo/scan.obj" "$tmp/pipe/out/cage.obj" "$tmp/cube.obj" "$tmp/out.obj" --quiet
expect_bad "deform: missing edited cage" "$cli" deform "$tmp/demo/scan.obj" "$tmp/pipe/out/cage.obj" "$tmp/does-not-exist.obj" "$tmp/out.obj" --quiet
expect_bad "deform: NaN in the scan" "$cli" deform "$tmp/nan.obj" "$tmp/cube.obj" "$tmp/cube.obj" "$tmp/out.obj" --quiet
if "$cli" bench-deform "$tmp/demo/scan.obj" "$tmp/pipe/out/cage.obj" --frames 10 --moved 3 --vertex-order deformer --json --quiet >"$tmp/bench_order.json" &&
   [ "$(json "$tmp/bench_order.json" 'd["vertex_order"] == "deformer" and d["cpu_fps"] > 0 and d["cpu_incremental_fps"] > 0')" = True ] &&
   [ "$(json "$tmp/bench_order.json" 'd["vertices"]')" = "$(json "$tmp/bench.json" 'd["vertices"]')" ] &&
   [ "$(json "$tmp/bench_order.json" 'd["triangles"]')" = "$(json "$tmp/bench.json" 'd["triangles"]')" ]
then pass "bench-deform --vertex-order deformer: the renumbered scan, same counts"; else cat "$tmp/bench_order.json"; fail "bench-deform --vertex-order"; fi
expect_bad "bench-deform: --vertex-order random" "$cli" bench-deform "$tmp/demo/scan.obj" "$tmp/pipe/out/cage.obj" --vertex-order random --quiet
expect_bad "bench-deform: --frames 0" "$cli" bench-deform "$tmp/demo/scan.obj" "$tmp/pipe/out/cage.obj" --frames 0 --quiet
# Saved bindings: bind once, deform from the .ckb = deform with binding anew (same bytes).
if "$cli" bind "$tmp/demo/scan.obj" "$tmp/pipe/out/cage.obj" "$tmp/scan.ckb" --local-frame --json --quiet >"$tmp/bind.json" &&
   [ "$(json "$tmp/bind.json" 'all(k in d for k in ("vertices","control_points","mode","bytes","bind_seconds")) and d["mode"] == "local_frame" and d["bytes"] > 100 * d["vertices"]')" = True ] &&
   "$cli" deform "$tmp/demo/scan.obj" "$tmp/scan.ckb" "$tmp/edited.obj" "$tmp/from_saved.obj" --quiet &&
   "$cli" deform "$tmp/demo/scan.obj" "$tmp/pipe/out/cage.obj" "$tmp/edited.obj" "$tmp/from_bind.obj" --local-frame --quiet &&
   cmp -s "$tmp/from_saved.obj" "$tmp/from_bind.obj"
then pass "bind: saved binding (.ckb) deforms exactly like binding anew"; else cat "$tmp/bind.json"; fail "bind/deform from .ckb"; fi
# Sharp features: one vertex per smooth sector (the demo block's edges and corners get copies).
if "$cli" bind "$tmp/demo/scan.obj" "$tmp/pipe/out/cage.obj" "$tmp/sectors.ckb" --sharp-angle 40 --json --quiet >"$tmp/sectors.json" &&
   [ "$(json "$tmp/sectors.json" 'd["vertices"] > d["scan_vertices"] > 100')" = True ] &&
   "$cli" deform "$tmp/demo/scan.obj" "$tmp/sectors.ckb" "$tmp/edited.obj" "$tmp/sectors_saved.obj" --quiet &&
   "$cli" deform "$tmp/demo/scan.obj" "$tmp/pipe/out/cage.obj" "$tmp/edited.obj" "$tmp/sectors_direct.obj" --sharp-angle 40 --quiet &&
   cmp -s "$tmp/sectors_saved.obj" "$tmp/sectors_direct.obj" &&
   [ "$(grep -c '^v ' "$tmp/sectors_saved.obj")" = "$(json "$tmp/sectors.json" 'd["vertices"]')" ]
then pass "bind/deform --sharp-angle: vertices duplicated per smooth sector, saved = direct"; else cat "$tmp/sectors.json"; fail "sector split"; fi
expect_bad "bind: --sharp-angle 200" "$cli" bind "$tmp/demo/scan.obj" "$tmp/pipe/out/cage.obj" "$tmp/x.ckb" --sharp-angle 200 --quiet
head -c 1000 "$tmp/scan.ckb" >"$tmp/truncated.ckb"
expect_bad "deform: truncated .ckb" "$cli" deform "$tmp/demo/scan.obj" "$tmp/truncated.ckb" "$tmp/edited.obj" "$tmp/out.obj" --quiet
expect_bad "deform: .ckb of another scan" "$cli" deform "$tmp/cube.obj" "$tmp/scan.ckb" "$tmp/edited.obj" "$tmp/out.obj" --quiet
expect_bad "bind: --threads -1" "$cli" bind "$tmp/demo/scan.obj" "$tmp/pipe/out/cage.obj" "$tmp/x.ckb" --threads -1 --quiet
expect_bad "bind: NaN in the scan" "$cli" bind "$tmp/nan.obj" "$tmp/cube.obj" "$tmp/x.ckb" --quiet

# 7. the C host sample
if "$host" "$tmp/demo/scan.drc" "$tmp/host.obj" 1 >"$tmp/host.out" 2>&1 && [ -s "$tmp/host.obj" ] && grep -q 'level 1' "$tmp/host.out"
then pass "c_host runs on the demo scan"; else cat "$tmp/host.out"; fail "c_host"; fi

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
