#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# packaging.install: `cmake --install` of the build tree into a scratch prefix, then checks that
#  - the prefix holds exactly the expected files (library + SONAME and development links, the
#    header, the CMake package, cagekit.pc, the CLI) and nothing else;
#  - the installed library and CLI depend on nothing in the build or source tree (readelf -d:
#    SONAME, NEEDED, RUNPATH; every NEEDED resolves), and the exported CMake target carries no
#    private dependency (CGAL, OpenSubdiv, Draco, ..., the SDK's static libraries);
#  - the installed header compiles alone as strict C99;
#  - samples/c_host builds as its own CMake project against the prefix only (and samples/cpp_host,
#    the C++ layer's host, when a C++ compiler is given)
#    (find_package(CageKit) -> CageKit::cagekit) and runs, and builds with
#    `cc $(pkg-config --cflags --libs cagekit)` and runs, on a scan made by the installed CLI;
#  - the installed tree still works after being moved (pkg-config and the CLI are relocatable).
# usage: check_install.sh CMAKE CC BUILD_DIR SOURCE_DIR BUILD_TYPE LIBDIR INCLUDEDIR BINDIR VERSION SOVERSION [CXX]
set -u
if [ $# -ne 10 ] && [ $# -ne 11 ]; then echo "usage: $0 CMAKE CC BUILD_DIR SOURCE_DIR BUILD_TYPE LIBDIR INCLUDEDIR BINDIR VERSION SOVERSION [CXX]" >&2; exit 2; fi
cmake="$1"; cc="$2"; build="$3"; source="$4"; build_type="$5"
libdir="$6"; includedir="$7"; bindir="$8"; version="$9"; soversion="${10}"; cxx="${11:-}"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"
failures=0; passed=0
pass() { passed=$((passed + 1)); echo "[ OK   ] $1"; }
fail() { failures=$((failures + 1)); echo "[ FAIL ] $1"; }
# Nothing from the environment may point the programs below at the build tree.
unset LD_LIBRARY_PATH PKG_CONFIG_PATH CMAKE_PREFIX_PATH CageKit_DIR

# 1. install
if "$cmake" --install "$build" --prefix "$prefix" >"$tmp/install.log" 2>&1
then pass "cmake --install into a scratch prefix"
else cat "$tmp/install.log"; fail "cmake --install"; echo "$passed passed, $failures failed"; exit 1; fi

# 2. exactly the expected files
config=$(echo "${build_type:-noconfig}" | tr '[:upper:]' '[:lower:]')
{
  echo "$bindir/cagekit"
  (cd "$source/include" && find cagekit -type f \( -name '*.h' -o -name '*.hpp' \)) | sed "s|^|$includedir/|"
  echo "$libdir/libcagekit.so"
  echo "$libdir/libcagekit.so.$soversion"
  echo "$libdir/libcagekit.so.$version"
  for f in CageKitConfig.cmake CageKitConfigVersion.cmake CageKitTargets.cmake "CageKitTargets-$config.cmake"; do
    echo "$libdir/cmake/CageKit/$f"
  done
  echo "$libdir/pkgconfig/cagekit.pc"
  echo "share/doc/cagekit/copyright"
} | LC_ALL=C sort >"$tmp/expected.txt"
(cd "$prefix" && find . ! -type d | sed 's|^\./||' | LC_ALL=C sort) >"$tmp/installed.txt"
if cmp -s "$tmp/expected.txt" "$tmp/installed.txt"
then pass "installed files: exactly $(wc -l <"$tmp/expected.txt") expected ones"
else diff "$tmp/expected.txt" "$tmp/installed.txt"; fail "installed files differ from the expected list (< expected, > installed)"; fi

lib="$prefix/$libdir/libcagekit.so.$version"
if [ -f "$lib" ] && [ ! -L "$lib" ] &&
   [ "$(readlink "$prefix/$libdir/libcagekit.so.$soversion")" = "libcagekit.so.$version" ] &&
   [ "$(readlink "$prefix/$libdir/libcagekit.so")" = "libcagekit.so.$soversion" ]
then pass "libcagekit.so -> libcagekit.so.$soversion -> libcagekit.so.$version (a file)"
else ls -l "$prefix/$libdir"; fail "library links"; fi

# 3. dynamic sections
readelf -d "$lib" >"$tmp/lib.dyn" 2>&1
readelf -d "$prefix/$bindir/cagekit" >"$tmp/cli.dyn" 2>&1
needed() { sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p' "$1"; }
if grep -q "(SONAME).*\[libcagekit.so.$soversion\]" "$tmp/lib.dyn"
then pass "SONAME libcagekit.so.$soversion"; else cat "$tmp/lib.dyn"; fail "SONAME"; fi
if [ -n "$(needed "$tmp/lib.dyn")" ] && ! needed "$tmp/lib.dyn" | grep -q -e / -e cagekit &&
   ! grep -q -e '(RPATH)' -e '(RUNPATH)' "$tmp/lib.dyn" &&
   ! grep -q -F -e "$build" -e "$source" "$tmp/lib.dyn"
then pass "library: NEEDED $(needed "$tmp/lib.dyn" | tr '\n' ' ')- no paths, no RPATH/RUNPATH"
else cat "$tmp/lib.dyn"; fail "library's dynamic section refers to the build tree or has a search path"; fi
if needed "$tmp/cli.dyn" | grep -qx "libcagekit.so.$soversion" &&
   ! needed "$tmp/cli.dyn" | grep -q / &&
   grep -q "(RUNPATH).*\[\$ORIGIN/../$libdir\]" "$tmp/cli.dyn" &&
   ! grep -q -F -e "$build" -e "$source" "$tmp/cli.dyn"
then pass "CLI: NEEDED libcagekit.so.$soversion, RUNPATH \$ORIGIN/../$libdir only"
else cat "$tmp/cli.dyn"; fail "CLI's dynamic section"; fi
if ldd "$lib" >"$tmp/lib.ldd" 2>&1 && ! grep -q 'not found' "$tmp/lib.ldd" && ! grep -q -F -e "$build" -e "$source" "$tmp/lib.ldd"
then pass "every NEEDED of the library resolves outside the build tree"; else cat "$tmp/lib.ldd"; fail "ldd of the library"; fi

# 4. the exported target: C interface only
targets="$prefix/$libdir/cmake/CageKit"
if grep -q 'add_library(CageKit::cagekit SHARED IMPORTED)' "$targets/CageKitTargets.cmake" &&
   ! cat "$targets"/CageKitTargets*.cmake | grep -v '^#' |
       grep -q -i -F -e "$build" -e "$source" -e LINK_LIBRARIES -e LINK_DEPENDENT -e cgal -e opensubdiv -e osdcpu \
                     -e draco -e eigen -e meshoptimizer -e openmesh -e Threads -e cagekit_core -e cagekit_subdiv
then pass "CageKit::cagekit: shared imported target without link dependencies or build-tree paths"
else cat "$targets"/CageKitTargets*.cmake; fail "exported target leaks dependencies or paths"; fi

# 5. the headers alone, strict C99: the main one, and the opt-in GL binding on top of it
printf '#include <cagekit/cagekit.h>\nint main(void) { return cagekit_abi_version() == CAGEKIT_ABI_VERSION ? 0 : 1; }\n' >"$tmp/header_only.c"
if "$cc" -std=c99 -Wall -Wextra -pedantic -Werror -fsyntax-only -I"$prefix/$includedir" "$tmp/header_only.c" >"$tmp/header.log" 2>&1
then pass "installed <cagekit/cagekit.h> compiles alone as C99 (-pedantic -Werror)"; else cat "$tmp/header.log"; fail "header as C99"; fi
printf '#include <cagekit/cagekit_gl.h>\nint main(void) { cagekit_gl_deformer_options o = CAGEKIT_GL_DEFORMER_OPTIONS_INIT; return (int)o.optimize_vertex_cache - 1; }\n' >"$tmp/gl_header_only.c"
if "$cc" -std=c99 -Wall -Wextra -pedantic -Werror -fsyntax-only -I"$prefix/$includedir" "$tmp/gl_header_only.c" >"$tmp/gl_header.log" 2>&1
then pass "installed <cagekit/cagekit_gl.h> compiles as C99 (-pedantic -Werror)"; else cat "$tmp/gl_header.log"; fail "GL header as C99"; fi
# ... and the header-only C++ layer over them, strict C++17 (when a C++ compiler is given)
if [ -n "$cxx" ]; then
  printf '#include <cagekit/cagekit_gl.hpp>\nint main() { return cagekit::abi_version() == CAGEKIT_ABI_VERSION ? 0 : 1; }\n' >"$tmp/hpp_only.cpp"
  if "$cxx" -std=c++17 -Wall -Wextra -pedantic -Werror -fsyntax-only -I"$prefix/$includedir" "$tmp/hpp_only.cpp" >"$tmp/hpp.log" 2>&1
  then pass "installed <cagekit/cagekit.hpp> and <cagekit/cagekit_gl.hpp> compile as C++17 (-pedantic -Werror)"
  else cat "$tmp/hpp.log"; fail "C++ headers as C++17"; fi
fi

# 6. the installed CLI runs from the prefix without LD_LIBRARY_PATH and makes the input scan
# resolves_to_prefix PROGRAM PREFIX: the dynamic loader picks PREFIX's libcagekit for PROGRAM.
resolves_to_prefix() {
  resolved=$(ldd "$1" | sed -n 's/^[[:space:]]*libcagekit\.so[^ ]* => \([^ ]*\) .*/\1/p')
  [ -n "$resolved" ] && [ "$(readlink -f "$resolved")" = "$(readlink -f "$2/$libdir/libcagekit.so.$version")" ]
}
if "$prefix/$bindir/cagekit" demo "$tmp/demo" --quiet >"$tmp/demo.log" 2>&1 && [ -s "$tmp/demo/scan.obj" ] &&
   resolves_to_prefix "$prefix/$bindir/cagekit" "$prefix"
then pass "installed cagekit runs (demo) with the installed libcagekit"; else cat "$tmp/demo.log"; ldd "$prefix/$bindir/cagekit"; fail "installed CLI"; fi

# 7. samples/c_host as its own CMake project against the install prefix only
if "$cmake" -S "$source/samples/c_host" -B "$tmp/c_host-cmake" -DCMAKE_C_COMPILER="$cc" -DCMAKE_BUILD_TYPE=Release \
     -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >"$tmp/c_host-configure.log" 2>&1 &&
   grep -qx "CageKit_DIR:PATH=$prefix/$libdir/cmake/CageKit" "$tmp/c_host-cmake/CMakeCache.txt" &&
   "$cmake" --build "$tmp/c_host-cmake" >"$tmp/c_host-build.log" 2>&1
then pass "samples/c_host configures (find_package(CageKit) in the prefix) and builds standalone"
else cat "$tmp/c_host-configure.log" "$tmp/c_host-build.log"; grep CageKit_DIR "$tmp/c_host-cmake/CMakeCache.txt"; fail "standalone c_host build"; fi
host="$tmp/c_host-cmake/cagekit_c_host"
if [ -x "$host" ] && "$host" "$tmp/demo/scan.obj" "$tmp/cmake.obj" 1 >"$tmp/cmake.out" 2>&1 &&
   grep -q 'level 1' "$tmp/cmake.out" && [ -s "$tmp/cmake.obj" ] && resolves_to_prefix "$host" "$prefix"
then pass "standalone c_host runs with the installed libcagekit"; else cat "$tmp/cmake.out"; fail "standalone c_host run"; fi

# 7b. samples/cpp_host (the C++ layer) as its own CMake project against the install prefix only
if [ -n "$cxx" ]; then
  cpp_host="$tmp/cpp_host-cmake/cagekit_cpp_host"
  mkdir -p "$tmp/cpp_host-out"
  if "$cmake" -S "$source/samples/cpp_host" -B "$tmp/cpp_host-cmake" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE=Release \
       -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >"$tmp/cpp_host-configure.log" 2>&1 &&
     "$cmake" --build "$tmp/cpp_host-cmake" >"$tmp/cpp_host-build.log" 2>&1 &&
     "$cpp_host" "$tmp/demo/scan.obj" "$tmp/cpp_host-out" 6 >"$tmp/cpp_host.out" 2>&1 &&
     grep -q 'rest pose within' "$tmp/cpp_host.out" && [ -s "$tmp/cpp_host-out/deformed.obj" ] &&
     resolves_to_prefix "$cpp_host" "$prefix"
  then pass "samples/cpp_host builds standalone against the prefix and runs the scan -> deform journey"
  else cat "$tmp/cpp_host-configure.log" "$tmp/cpp_host-build.log" "$tmp/cpp_host.out"; fail "standalone cpp_host"; fi
fi

# 8. samples/c_host with pkg-config
export PKG_CONFIG_PATH="$prefix/$libdir/pkgconfig"
if [ "$(pkg-config --modversion cagekit 2>&1)" = "$version" ] &&
   [ "$(cd "$(pkg-config --variable=libdir cagekit)" && pwd -P)" = "$(cd "$prefix/$libdir" && pwd -P)" ] &&
   [ "$(cd "$(pkg-config --variable=includedir cagekit)" && pwd -P)" = "$(cd "$prefix/$includedir" && pwd -P)" ]
then pass "pkg-config cagekit: version $version, libdir and includedir in the prefix"
else pkg-config --print-variables --modversion cagekit; cat "$PKG_CONFIG_PATH/cagekit.pc"; fail "pkg-config variables"; fi
# shellcheck disable=SC2046 # the flags are meant to split
if "$cc" -std=c99 -Wall -Wextra -pedantic -Werror "$source/samples/c_host/c_host.c" -o "$tmp/c_host_pc" \
     $(pkg-config --cflags --libs cagekit) >"$tmp/pc-build.log" 2>&1 &&
   LD_LIBRARY_PATH="$prefix/$libdir" "$tmp/c_host_pc" "$tmp/demo/scan.obj" "$tmp/pc.obj" 1 >"$tmp/pc.out" 2>&1 &&
   grep -q 'level 1' "$tmp/pc.out" && cmp -s "$tmp/pc.obj" "$tmp/cmake.obj" &&
   (LD_LIBRARY_PATH="$prefix/$libdir"; export LD_LIBRARY_PATH; resolves_to_prefix "$tmp/c_host_pc" "$prefix")
then pass "c_host built with \`cc \$(pkg-config --cflags --libs cagekit)\` runs, same output as the CMake build"
else cat "$tmp/pc-build.log" "$tmp/pc.out"; fail "pkg-config c_host"; fi

# 9. the installed tree moved elsewhere
mv "$prefix" "$tmp/moved"
export PKG_CONFIG_PATH="$tmp/moved/$libdir/pkgconfig"
if "$tmp/moved/$bindir/cagekit" version >"$tmp/moved.out" 2>&1 && grep -q "cagekit $version" "$tmp/moved.out" &&
   [ "$(cd "$(pkg-config --variable=libdir cagekit)" && pwd -P)" = "$(cd "$tmp/moved/$libdir" && pwd -P)" ]
then pass "moved install tree: the CLI finds its library, pkg-config the moved prefix"
else cat "$tmp/moved.out"; pkg-config --variable=libdir cagekit; fail "relocated install tree"; fi

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
