#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# packaging.deb: `cpack -G DEB` of the build tree into a scratch folder (not the source tree),
# then, with dpkg-deb, checks the package's files (library + links, header, CMake package,
# cagekit.pc, CLI: exactly these), its control fields (Package, Version, Maintainer, a Depends line
# computed by dpkg-shlibdeps, shlibs for libcagekit.so.2), and that the unpacked tree works:
# the CLI runs and samples/c_host builds with pkg-config against it and runs.
# usage: check_deb.sh CPACK CC BUILD_DIR SOURCE_DIR LIBDIR INCLUDEDIR BINDIR VERSION SOVERSION
set -u
if [ $# -ne 9 ]; then echo "usage: $0 CPACK CC BUILD_DIR SOURCE_DIR LIBDIR INCLUDEDIR BINDIR VERSION SOVERSION" >&2; exit 2; fi
cpack="$1"; cc="$2"; build="$3"; source="$4"; libdir="$5"; includedir="$6"; bindir="$7"
version="$8"; soversion="$9"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
failures=0; passed=0
pass() { passed=$((passed + 1)); echo "[ OK   ] $1"; }
fail() { failures=$((failures + 1)); echo "[ FAIL ] $1"; }
unset LD_LIBRARY_PATH PKG_CONFIG_PATH

# 1. the package, made in the scratch folder
arch=$(dpkg --print-architecture)
deb="$tmp/out/cagekit_${version}_${arch}.deb"
if "$cpack" -G DEB --config "$build/CPackConfig.cmake" -B "$tmp/out" >"$tmp/cpack.log" 2>&1 &&
   [ -f "$deb" ] && [ "$(find "$tmp/out" -maxdepth 1 -name "*.deb" | wc -l)" -eq 1 ] &&
   [ ! -e "$source/_CPack_Packages" ] && [ -z "$(ls "$source"/*.deb 2>/dev/null)" ]
then pass "cpack -G DEB makes $(basename "$deb") in the scratch folder only"
else cat "$tmp/cpack.log"; ls -l "$tmp/out"; fail "cpack -G DEB"; echo "$passed passed, $failures failed"; exit 1; fi

# 2. its files
{
  echo "./usr/$bindir/cagekit"
  (cd "$source/include" && find cagekit -type f \( -name '*.h' -o -name '*.hpp' \)) | sed "s|^|./usr/$includedir/|"
  echo "./usr/$libdir/libcagekit.so -> libcagekit.so.$soversion"
  echo "./usr/$libdir/libcagekit.so.$soversion -> libcagekit.so.$version"
  echo "./usr/$libdir/libcagekit.so.$version"
  for f in CageKitConfig.cmake CageKitConfigVersion.cmake CageKitTargets.cmake CageKitTargets-*.cmake; do
    echo "./usr/$libdir/cmake/CageKit/$f"
  done
  echo "./usr/$libdir/pkgconfig/cagekit.pc"
  echo "./usr/share/doc/cagekit/copyright"
} | LC_ALL=C sort >"$tmp/expected.txt"
dpkg-deb -c "$deb" >"$tmp/contents.txt" 2>&1
# "perms owner/group size date time path [-> target]"; the per-config targets file by pattern
awk '$1 !~ /^d/ { $1 = $2 = $3 = $4 = $5 = ""; sub(/^ +/, ""); print }' "$tmp/contents.txt" |
  sed 's|/CageKitTargets-[a-z]*\.cmake$|/CageKitTargets-*.cmake|' | LC_ALL=C sort >"$tmp/packaged.txt"
if cmp -s "$tmp/expected.txt" "$tmp/packaged.txt"
then pass "package files: exactly $(wc -l <"$tmp/expected.txt") expected ones (library, links, header, CMake package, cagekit.pc, CLI, copyright)"
else diff "$tmp/expected.txt" "$tmp/packaged.txt"; fail "package files differ from the expected list (< expected, > packaged)"; fi

# 3. control fields
field() { dpkg-deb -f "$deb" "$1"; }
depends=$(field Depends)
if [ "$(field Package)" = cagekit ] && [ "$(field Version)" = "$version" ] && [ "$(field Architecture)" = "$arch" ] &&
   [ "$(field Maintainer)" = "CageKit developers" ] && field Description | grep -q 'GPL-3.0-or-later'
then pass "control: Package cagekit, Version $version, Architecture $arch, Maintainer, license in Description"
else dpkg-deb -I "$deb"; fail "control fields"; fi
if echo "$depends" | grep -q 'libc6 (>= ' && echo "$depends" | grep -q 'libstdc++6 (>= ' &&
   ! echo "$depends" | grep -q cagekit
then pass "Depends (dpkg-shlibdeps): $depends"
else dpkg-deb -I "$deb"; fail "Depends line missing or incomplete: '$depends'"; fi
if dpkg-deb -I "$deb" shlibs 2>/dev/null | grep -qx "libcagekit $soversion cagekit (>= $version)"
then pass "shlibs: libcagekit $soversion cagekit (>= $version)"; else dpkg-deb -I "$deb" shlibs; fail "shlibs control file"; fi

# 4. the unpacked tree works: stripped library, CLI, a pkg-config build of c_host
root="$tmp/root"
dpkg-deb -x "$deb" "$root"
if ! readelf -S "$root/usr/$libdir/libcagekit.so.$version" | grep -q '\.debug_info' &&
   readelf -d "$root/usr/$libdir/libcagekit.so.$version" | grep -q "(SONAME).*\[libcagekit.so.$soversion\]"
then pass "packaged library is stripped, SONAME libcagekit.so.$soversion"; else fail "packaged library"; fi
if "$root/usr/$bindir/cagekit" version >"$tmp/version.out" 2>&1 && grep -q "cagekit $version" "$tmp/version.out"
then pass "packaged CLI runs from the unpacked tree: $(cat "$tmp/version.out")"; else cat "$tmp/version.out"; fail "packaged CLI"; fi
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
export PKG_CONFIG_PATH="$root/usr/$libdir/pkgconfig"
# shellcheck disable=SC2046 # the flags are meant to split
if "$cc" -std=c99 -Wall -Wextra -pedantic -Werror "$source/samples/c_host/c_host.c" -o "$tmp/c_host" \
     $(pkg-config --cflags --libs cagekit) >"$tmp/build.log" 2>&1 &&
   LD_LIBRARY_PATH="$root/usr/$libdir" "$tmp/c_host" "$tmp/cube.obj" "$tmp/cube2.obj" 2 >"$tmp/host.out" 2>&1 &&
   grep -q 'level 2, 98 vertices, 96 quads, genus 0' "$tmp/host.out"
then pass "c_host built with pkg-config against the unpacked package runs: $(grep level "$tmp/host.out")"
else cat "$tmp/build.log" "$tmp/host.out"; fail "c_host against the unpacked package"; fi

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
