#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Compares the ABI of a built libcagekit with the committed baseline (tests/abi/README.md).
#   check_abi.sh LIBCAGEKIT_SO PUBLIC_HEADERS_DIR BASELINE.abi OUT_CURRENT.abi
#   check_abi.sh --update LIBCAGEKIT_SO PUBLIC_HEADERS_DIR BASELINE.abi   (rewrites the baseline)
# Fails on incompatible changes: removed or changed functions, changed parameter/return types,
# changed layouts of the public structs (except fields appended at the end of the versioned
# structs, see abi.suppr) and enum values; added functions and added enumerators pass.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
update=0
if [ "${1:-}" = "--update" ]; then update=1; shift; fi
lib=$1 headers=$2 baseline=$3
out=${4:-$(mktemp)}

command -v abidw >/dev/null 2>&1 && command -v abidiff >/dev/null 2>&1 ||
  { echo "check_abi: abidw/abidiff not installed (Debian: abigail-tools); skipped"; exit 77; }
if ! readelf -S "$lib" 2>/dev/null | grep -q '\.debug_info'; then
  echo "check_abi: $lib has no DWARF (.debug_info); the C API layer must be compiled with -g" >&2
  exit 1
fi

# --headers-dir + --drop-private-types + --exported-interfaces-only: only the exported cagekit_*
# functions and the types defined in the public header are kept; the C++ objects behind the
# opaque handles (sdk/capi/handles.h) are private and stay opaque.
# --no-corpus-path / --no-comp-dir-path / --no-show-locs: nothing from the build path or
# source line numbers, so the output depends only on the ABI. Sorted type ids by hash keep the
# file stable when unrelated declarations move.
abidw --headers-dir "$headers" --drop-private-types --exported-interfaces-only --no-corpus-path \
  --no-comp-dir-path --no-show-locs --no-architecture --no-elf-needed --type-id-style hash \
  --out-file "$out.raw" "$lib"
# Translation units are named by their absolute source path: keep it relative to the checkout.
root=$(cd "$headers/../.." && pwd)
sed "s|path='$root/|path='|" "$out.raw" >"$out"
rm -f "$out.raw"

if [ "$update" = 1 ]; then
  cp "$out" "$baseline"
  echo "check_abi: baseline written to $baseline ($(grep -c '<function-decl' "$baseline") functions)"
  exit 0
fi

set +e
abidiff --suppressions "$here/abi.suppr" --no-added-syms "$baseline" "$out" >"$out.diff" 2>&1
status=$?
set -e
# abidiff's exit status is a bit field: 1 error, 2 usage error, 4 ABI change, 8 incompatible
# ABI change. Any change left after the suppressions (a sub-type change of a public struct, a
# changed enum value, a removed function) fails.
if [ "$status" -ne 0 ]; then
  cat "$out.diff"
  echo "check_abi: ABI differs from $baseline (abidiff status $status)." >&2
  echo "check_abi: an intended change needs CAGEKIT_ABI_VERSION bumped and the baseline regenerated (tests/abi/README.md)" >&2
  exit 1
fi
added=$(abidiff --suppressions "$here/abi.suppr" "$baseline" "$out" 2>/dev/null | grep -c "^  \[A\]" || true)
echo "check_abi: compatible with $baseline ($(grep -c '<function-decl' "$out") functions now, $added added)"
