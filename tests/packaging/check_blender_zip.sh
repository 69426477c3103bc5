#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# packaging.blender_zip: the Blender add-on zip (what target blender_addon_zip makes, here into a
# scratch folder) holds the add-on, the cagekit Python package, the built libcagekit itself (its
# RUNPATH set to $ORIGIN/libs by packaging/bundle_libs.py) and its bundled libraries in cagekit/libs/.
# usage: check_blender_zip.sh CMAKE BINDINGS_DIR LIBRARY SOVERSION PYTHON
set -u
if [ $# -ne 5 ]; then echo "usage: $0 CMAKE BINDINGS_DIR LIBRARY SOVERSION PYTHON" >&2; exit 2; fi
cmake="$1"; bindings="$2"; library="$3"; soversion="$4"; python="$5"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
failures=0; passed=0
pass() { passed=$((passed + 1)); echo "[ OK   ] $1"; }
fail() { failures=$((failures + 1)); echo "[ FAIL ] $1"; }

zip="$tmp/cagekit_blender.zip"
if "$cmake" -DSOURCE_DIR="$bindings" -DLIBRARY="$library" -DSONAME="libcagekit.so.$soversion" -DSTAGE="$tmp/stage" -DZIP="$zip" \
     -DPYTHON="$python" -P "$bindings/blender/make_addon_zip.cmake" >"$tmp/zip.log" 2>&1 && [ -s "$zip" ]
then pass "add-on zip made"; else cat "$tmp/zip.log"; fail "make_addon_zip.cmake"; echo "$passed passed, $failures failed"; exit 1; fi

"$cmake" -E tar tf "$zip" | sed 's|/$||' | LC_ALL=C sort >"$tmp/list.txt"
lib_entry="cagekit_blender/cagekit/libcagekit.so.$soversion"
if grep -qx 'cagekit_blender/__init__.py' "$tmp/list.txt" && grep -qx 'cagekit_blender/cagekit/__init__.py' "$tmp/list.txt" &&
   grep -qx "$lib_entry" "$tmp/list.txt" && [ "$(cut -d/ -f1 "$tmp/list.txt" | sort -u)" = cagekit_blender ] &&
   grep -q '^cagekit_blender/cagekit/libs/libosdCPU\.so\.' "$tmp/list.txt" &&
   ! grep -q -e __pycache__ -e '\.pyc$' "$tmp/list.txt"
then pass "zip: one folder cagekit_blender/ with the add-on, the cagekit package, $lib_entry and cagekit/libs/"
else cat "$tmp/list.txt"; fail "zip contents"; fi

mkdir "$tmp/x"
if (cd "$tmp/x" && "$cmake" -E tar xf "$zip") && [ -f "$tmp/x/$lib_entry" ] && [ ! -L "$tmp/x/$lib_entry" ] &&
   nm -D --defined-only "$tmp/x/$lib_entry" >"$tmp/zip.sym" && nm -D --defined-only "$library" >"$tmp/built.sym" &&
   cmp -s "$tmp/zip.sym" "$tmp/built.sym" && [ -s "$tmp/built.sym" ] &&
   readelf -d "$tmp/x/$lib_entry" | grep -q "(SONAME).*\[libcagekit.so.$soversion\]" &&
   readelf -d "$tmp/x/$lib_entry" | grep -q '(RUNPATH).*\[\$ORIGIN/libs\]'
then pass "the zip's libcagekit.so.$soversion is the built library (a file, the same exported symbols, SONAME libcagekit.so.$soversion, RUNPATH \$ORIGIN/libs)"
else ls -l "$tmp/x/cagekit_blender/cagekit" 2>&1; fail "library in the zip"; fi

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
