#!/usr/bin/env bash
# Installs the Debian 12 packages CageKit needs. Idempotent: packages already present are skipped.
# Run as root or with sudo available.
#   bash packaging/install-deps.sh           everything: the build and every test (README command (b))
#   bash packaging/install-deps.sh --build   only what the library, the CLI and `cagekit demo` need
#                                            (README command (a); configure with -DCAGEKIT_BUILD_TESTS=OFF)
# All go through one `apt-get install --no-install-recommends` (Blender and FreeCAD, test-only, are
# the bulk: freecad 0.20.2 took 1m40s there, 122 packages, 151 MB downloaded, 958 MB on disk).
# libocct-data-exchange-dev (OpenCASCADE 7.6, optional: samples/step_export, `cagekit export-surfaces`)
# pulls libocct-{foundation,modeling-data,modeling-algorithms,ocaf,visualization}-dev with it.
set -euo pipefail

# The library (CGAL, Eigen, OpenMesh, OpenSubdiv, Draco, meshoptimizer, EGL/GL headers, libpng for
# pictures), the CLI (CLI11, nlohmann-json) and the demo's headless pictures (Mesa's llvmpipe).
BUILD_PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libcgal-dev libeigen3-dev libopenmesh-dev libosd-dev libdraco-dev libmeshoptimizer-dev
  libegl-dev libgles-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libpng-dev
  nlohmann-json3-dev libcli11-dev
)
# The tests: GoogleTest, the Python package and its hosts (Blender, FreeCAD), Dask's distributed
# (cagekit.batch on a LocalCluster), the sanitizer and fuzzer toolchain, the ABI checker, OpenCASCADE
# (STEP export), the packaging tools (the wheel: patchelf, pip, venv, setuptools, wheel) and mypy (the
# Python package's type hints, test_typing.py).
TEST_PACKAGES=(
  libgtest-dev python3 python3-numpy python3-mypy python3-distributed binutils blender freecad xvfb xauth
  patchelf python3-pip python3-venv python3-setuptools python3-wheel
  clang libclang-rt-14-dev
  abigail-tools
  libocct-data-exchange-dev
)

case "${1:-}" in
  --build) PACKAGES=("${BUILD_PACKAGES[@]}") ;;
  "") PACKAGES=("${BUILD_PACKAGES[@]}" "${TEST_PACKAGES[@]}") ;;
  *) echo "install-deps: unknown option '$1' (none: everything; --build: the build and the demo only)" >&2; exit 64 ;;
esac

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1
  fi
fi
echo "install-deps: installing ${missing[*]}"
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get update -q
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
