#!/bin/sh
# samples/cpp_host, the C++ layer's host: the scan -> cage -> fit -> bind -> deform journey on the
# demo's generated scan (a noisy block), its figures and files, and the error convention.
# usage: check_cpp_host.sh CAGEKIT CPP_HOST
set -u
cli="$1"; host="$2"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
failures=0; passed=0
pass() { passed=$((passed + 1)); echo "[ OK   ] $1"; }
fail() { failures=$((failures + 1)); echo "[ FAIL ] $1"; }
json() { /usr/bin/env python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2], {'d': d}))" "$@"; }

"$cli" demo "$tmp/demo" --quiet >/dev/null 2>&1 || { echo "cagekit demo failed"; exit 1; }
mkdir -p "$tmp/out"
if "$host" "$tmp/demo/scan.obj" "$tmp/out" 6 >"$tmp/host.out" 2>"$tmp/host.err"; then pass "cpp_host exits 0"
else cat "$tmp/host.out" "$tmp/host.err"; fail "cpp_host run"; fi

# The printed figures: a 6-quad cage, the fit lowers the RMS, the unedited cage gives the scan back.
if /usr/bin/env python3 - "$tmp/host.out" <<'PY'
import re, sys
line = open(sys.argv[1]).read()
m = re.search(r"cage (\d+) faces \((\d+) quads\), fit RMS ([0-9.e+-]+) -> ([0-9.e+-]+) of the diagonal in (\d+) passes, "
              r"rest pose within ([0-9.e+-]+) of the diagonal, (\d+) vertices deformed", line)
assert m, line
faces, quads, rms0, rms1, passes, rest, deformed = m.groups()
assert int(faces) == 6 and int(quads) == 6, line
assert float(rms1) < float(rms0) and int(passes) >= 1, line
assert float(rest) < 1e-6, line
PY
then pass "cpp_host: 6-quad cage, fit lowers the RMS, rest pose within 1e-6 of the diagonal"
else cat "$tmp/host.out"; fail "cpp_host figures"; fi

# The files: the fitted cage keeps its 12 creases; the edited scan is the scan stretched by 1.2 in x.
"$cli" info "$tmp/out/cage.obj" --json >"$tmp/cage.json" 2>/dev/null
"$cli" info "$tmp/demo/scan.obj" --json >"$tmp/scan.json" 2>/dev/null
"$cli" info "$tmp/out/deformed.obj" --json >"$tmp/deformed.json" 2>/dev/null
if [ "$(json "$tmp/cage.json" "d['quads'] == 6 and d['creases'] == 12")" = True ] &&
   /usr/bin/env python3 - "$tmp/scan.json" "$tmp/deformed.json" <<'PY'
import json, sys
s, d = (json.load(open(p)) for p in sys.argv[1:3])
assert d["vertices"] == s["vertices"] and d["faces"] == s["faces"], (s, d)
wx = lambda m: m["bbox_max"][0] - m["bbox_min"][0]
wy = lambda m: m["bbox_max"][1] - m["bbox_min"][1]
assert abs(wx(d) / wx(s) - 1.2) < 0.02, (wx(s), wx(d))   # stretched by the cage edit
assert abs(wy(d) / wy(s) - 1.0) < 0.02, (wy(s), wy(d))   # not in y
PY
then pass "cpp_host: cage.obj has 6 quads and 12 creases; deformed.obj is the scan stretched 1.2x in x only"
else cat "$tmp/cage.json" "$tmp/deformed.json"; fail "cpp_host outputs"; fi

# Bad input: exit 2 and one line naming the failing C function and the file.
"$host" "$tmp/does-not-exist.obj" "$tmp/out" >"$tmp/bad.out" 2>"$tmp/bad.err"; code=$?
if [ "$code" -eq 2 ] && grep -q 'cagekit_mesh_read_file failed' "$tmp/bad.err" && grep -q 'does-not-exist.obj' "$tmp/bad.err"
then pass "cpp_host: a missing scan is exit 2 with the C function's name and the SDK's message"
else cat "$tmp/bad.err"; fail "cpp_host bad input (exit $code)"; fi
"$host" >/dev/null 2>&1; code=$?
if [ "$code" -eq 64 ]; then pass "cpp_host: usage error is exit 64"; else fail "cpp_host usage (exit $code)"; fi

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
