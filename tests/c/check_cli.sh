#!/bin/sh
# End-to-end checks of the `cagekit` CLI and the C host sample: demo output, info --json keys,
# conversions that keep cage tags, fandisk through Draco, and the bad-input convention
# (one line on stderr naming the file, exit code 2, no output file left behind).
# usage: check_cli.sh CAGEKIT C_HOST SHARED_MESHES_DIR
set -u
cli="$1"; host="$2"; meshes="$3"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
failures=0; passed=0
pass() { passed=$((passed + 1)); echo "[ OK   ] $1"; }
fail() { failures=$((failures + 1)); echo "[ FAIL ] $1"; }
json() { /usr/bin/env python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2], {'d': d}))" "$@"; }

# 1. demo
if "$cli" demo "$tmp/demo" --quiet >"$tmp/demo.out" 2>&1 &&
   for f in scan.obj scan.ply scan.drc cage.obj cage.drc cage_level3.obj scan_level1_limit.obj summary.json; do
     [ -s "$tmp/demo/$f" ] || exit 1; done; then pass "demo writes its outputs"; else cat "$tmp/demo.out"; fail "demo"; fi

if [ "$(json "$tmp/demo/summary.json" "d['cage']['quads'] == 6 and d['cage']['creases'] == 12 and d['cage']['triangles'] == 0 and d['cage']['level3_limit_hausdorff_rel'] < 1e-3 and d['scan']['valid']")" = True ]
then pass "demo: the scan of a block simplifies to a 6-quad cage with 12 creases whose limit is within 0.1% of the scan"; else cat "$tmp/demo/summary.json"; fail "demo pipeline"; fi

# 2. info --json on the demo scan
"$cli" info "$tmp/demo/scan.obj" --json >"$tmp/info.json" 2>/dev/null
if [ "$(json "$tmp/info.json" "all(k in d for k in 'vertices faces quads triangles boundary_loops genus manifold bbox_diagonal creases corners'.split()) and d['genus'] == 0 and d['boundary_loops'] == 0 and d['manifold'] and d['triangles'] == d['faces']")" = True ]
then pass "info --json keys and values"; else cat "$tmp/info.json"; fail "info --json"; fi

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
head -c 200 "$tmp/demo/scan.drc" >"$tmp/truncated.drc"
expect_bad "truncated Draco" "$cli" convert "$tmp/truncated.drc" "$tmp/out.obj" --quiet
expect_bad "missing file" "$cli" info "$tmp/does-not-exist.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 2 1 3\nf 1 2 3\n' >"$tmp/nonmanifold.obj"
expect_bad "invalid cage for subdivide" "$cli" subdivide "$tmp/nonmanifold.obj" "$tmp/out.obj" --levels 1 --quiet

# 8. structure-preserving simplification to a cage with creases
rocker="$meshes/rocker-arm.obj"
if [ -f "$rocker" ]; then
  if "$cli" simplify "$rocker" "$tmp/rocker6.obj" --faces 6 --cage --json --quiet --clusters "$tmp/rocker-clusters.ply" >"$tmp/rocker.json" &&
     [ "$(json "$tmp/rocker.json" "d['invalid_faces'] == 0 and d['non_manifold_edges'] == 0 and d['polygons'] <= 12 and d['faces'] == d['quads'] + d['triangles'] + d['pentagons'] and d['other_polygons'] == 0 and all(k in d for k in 'polygons faces vertices quads triangles pentagons invalid_faces creases l2_error l21_error hausdorff_rel hausdorff_sym_rel seconds'.split())")" = True ] &&
     [ "$(grep -c '^element face 20088' "$tmp/rocker-clusters.ply")" = 1 ] && "$cli" info "$tmp/rocker6.obj" --json >"$tmp/r6.json" &&
     [ "$(json "$tmp/r6.json" "d['valid'] and d['genus'] == 1")" = True ]
  then pass "simplify rocker-arm to a coarse cage (valid, genus kept, clusters file)"; else cat "$tmp/rocker.json" "$tmp/r6.json"; fail "simplify rocker-arm"; fi
else
  echo "[ SKIP ] simplify checks: $rocker not present"
fi
expect_bad "simplify of a corrupt file" "$cli" simplify "$tmp/badindex.obj" "$tmp/out.obj" --faces 10 --quiet

# 7. the C host sample
if "$host" "$tmp/demo/scan.drc" "$tmp/host.obj" 1 >"$tmp/host.out" 2>&1 && [ -s "$tmp/host.obj" ] && grep -q 'level 1' "$tmp/host.out"
then pass "c_host runs on the demo scan"; else cat "$tmp/host.out"; fail "c_host"; fi

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
