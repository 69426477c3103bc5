#!/bin/sh
# `cagekit render` end to end (issue 24): pictures of the size asked for, covering a plausible share
# of the image, crease colour exactly when --creases is given, the error map's legend; items in
# the command line's order; the bad-input and usage conventions (one line on stderr, exit 2 / 64,
# no file written); no EGL: the SDK's message and exit 2. Inputs are generated here: a creased
# quad cube (cage) and the smooth cube's limit surface at level 3 (the "scan").
# Exit 77 (skipped) when no headless EGL display can be made here at all.
# usage: check_cli_render.sh CAGEKIT PNG_CHECK_PY
set -u
cli="$1"; png="$2"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
failures=0; passed=0
pass() { passed=$((passed + 1)); echo "[ OK   ] $1"; }
fail() { failures=$((failures + 1)); echo "[ FAIL ] $1"; }
check_png() { /usr/bin/env python3 "$png" "$@"; }
crease=230,38,140      # the default crease colour (0.90, 0.15, 0.55)
yellow=253,231,37      # viridis' last colour: the top of the legend bar

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
{ cat "$tmp/cube.obj"
  for e in "0 1" "2 3" "4 5" "6 7" "0 2" "1 3" "4 6" "5 7" "0 4" "1 5" "2 6" "3 7"; do echo "t crease 2/1/0 $e 10"; done
} >"$tmp/creased.obj"
"$cli" subdivide "$tmp/cube.obj" "$tmp/scan.obj" --levels 3 --limit --quiet || { echo "cannot make the scan"; exit 1; }

# 1. scan | creased cage with its control edges | error map (the cage again, coloured by distance)
if "$cli" render "$tmp/three.png" --mesh "$tmp/scan.obj" --cage "$tmp/creased.obj" --cage "$tmp/creased.obj" \
     --error "$tmp/scan.obj" --wire --creases --size 600x240 >"$tmp/out" 2>"$tmp/err"; then
  pass "render scan | cage | error map: exit 0"
else
  code=$?
  if grep -q "EGL\|without the render module" "$tmp/err"; then cat "$tmp/err"; echo "SKIP: no headless EGL here"; exit 77; fi
  cat "$tmp/err"; fail "render scan | cage | error map: exit $code"
fi
if check_png "$tmp/three.png" --size 600x240 --min-share 0.15 --max-share 0.8 --color "$crease,50" --color "$yellow,5"
then pass "600 x 240 PNG, 15-80 % covered, crease colour and the legend's yellow present"; else fail "the picture"; fi
if grep -q "two-sided distance to .*scan.obj: max" "$tmp/err" && grep -q "wrote .*three.png (600 x 240, 3 items, 1 view" "$tmp/err"
then pass "summary: the two-sided distance of each cage and what was written"; else cat "$tmp/err"; fail "summary lines"; fi
# Each column holds its item: the left third (the scan) has no crease colour, the others do.
if /usr/bin/env python3 - "$png" "$tmp/three.png" <<'PY'
import sys
sys.path.insert(0, __import__("os").path.dirname(sys.argv[1]))
from png_check import read_png
w, h, rows = read_png(sys.argv[2])
def creases(x0, x1):
    return sum(1 for row in rows for x in range(x0, x1) if all(abs(row[4 * x + k] - c) <= 1 for k, c in enumerate((230, 38, 140))))
thirds = [creases(i * w // 3, (i + 1) * w // 3) for i in range(3)]
print("crease pixels per column:", thirds)
sys.exit(0 if thirds[0] == 0 and thirds[1] > 20 and thirds[2] > 20 else 1)
PY
then pass "items in the order given: scan (no creases) | cage | cage"; else fail "column order"; fi

# 2. no --creases: not one pixel of the crease colour
if "$cli" render "$tmp/plain.png" --cage "$tmp/creased.obj" --wire --size 200x200 --quiet 2>"$tmp/err" &&
   check_png "$tmp/plain.png" --size 200x200 --min-share 0.1 --no-color "$crease"
then pass "without --creases no crease colour"; else cat "$tmp/err"; fail "without --creases"; fi

# 3. one item, four views, default size: 400 x 400 per tile in a 2 x 2 grid
if "$cli" render "$tmp/views.png" --mesh "$tmp/scan.obj" --views front,side,top,iso --quiet 2>"$tmp/err" &&
   check_png "$tmp/views.png" --size 800x800 --min-share 0.1 --max-share 0.8
then pass "one mesh, four views: 800 x 800 (2 x 2 tiles of 400)"; else cat "$tmp/err"; fail "four views"; fi

# 4. bad input (exit 2) and usage errors (exit 64): one line (and the --help hint), no file written
expect() {  # expect CODE WHAT ARGS...
  want="$1"; what="$2"; shift 2
  rm -f "$tmp/bad.png" "$tmp/bad.jpg"
  "$cli" render "$@" >"$tmp/out" 2>"$tmp/err"; code=$?
  lines=$(wc -l <"$tmp/err")
  if [ "$code" -eq "$want" ] && [ ! -e "$tmp/bad.png" ] && [ ! -e "$tmp/bad.jpg" ] && head -1 "$tmp/err" | grep -q '^cagekit: ' &&
     { { [ "$want" -eq 2 ] && [ "$lines" -eq 1 ]; } || { [ "$want" -eq 64 ] && [ "$lines" -eq 2 ]; }; }
  then pass "$what: exit $want, one line, no file"; else cat "$tmp/err"; fail "$what (exit $code)"; fi
}
expect 2 "a missing mesh file" "$tmp/bad.png" --mesh "$tmp/missing.obj"
expect 2 "a cage file that is no mesh" "$tmp/bad.png" --cage "$png"
expect 64 "no item" "$tmp/bad.png"
expect 64 "an unknown view" "$tmp/bad.png" --mesh "$tmp/scan.obj" --views front,back
expect 64 "a size of 0" "$tmp/bad.png" --mesh "$tmp/scan.obj" --size 0x100
expect 64 "a size that is no WxH" "$tmp/bad.png" --mesh "$tmp/scan.obj" --size 300
expect 64 "--error without a cage" "$tmp/bad.png" --mesh "$tmp/scan.obj" --error "$tmp/scan.obj"
expect 64 "an unknown colour map" "$tmp/bad.png" --cage "$tmp/creased.obj" --error "$tmp/scan.obj" --colormap jet
expect 64 "--level out of range" "$tmp/bad.png" --cage "$tmp/creased.obj" --level 7
expect 64 "more titles than items" "$tmp/bad.png" --mesh "$tmp/scan.obj" --title a --title b
expect 64 "an output that is not .png" "$tmp/bad.jpg" --mesh "$tmp/scan.obj"

# 5. no EGL library: the SDK's message naming it, exit 2, no file
rm -f "$tmp/noegl.png"
CAGEKIT_EGL_LIBRARY=/nonexistent/libEGL-cagekit-test.so.1 "$cli" render "$tmp/noegl.png" --mesh "$tmp/scan.obj" --quiet \
  >"$tmp/out" 2>"$tmp/err"; code=$?
if [ "$code" -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q "libEGL-cagekit-test" "$tmp/err" && [ ! -e "$tmp/noegl.png" ]
then pass "no EGL: exit 2, the SDK's one-line message naming the library, no file"; else cat "$tmp/err"; fail "no EGL (exit $code)"; fi

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
