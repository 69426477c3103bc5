#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# A stand-in for `cagekit pipeline SCAN OUTDIR [options]` in the tests of `cagekit batch`
# (check_batch_cli.py, its worker command): the outcome comes from the scan's file name, so the
# batch's isolation and classification are tested without running the SDK. It records its
# arguments in OUTDIR/argv.txt.
scan=$1
out=$2
mkdir -p "$out" || exit 2
printf '%s\n' "$@" > "$out/argv.txt"
case "$(basename "$scan")" in
  crash*) kill -SEGV $$ ;;
  hang*) sleep 60; exit 0 ;;
  error*) echo "cagekit: $scan: no faces (a point cloud is not a mesh)" >&2; exit 2 ;;
  throw*) echo "cagekit: std::length_error" >&2; exit 1 ;;
  oom*) echo "cagekit: $scan: out of memory" >&2; exit 2 ;;
  nooutput*) exit 0 ;;
esac
# The unit cube as a cage; holes*: without its top face.
{
  echo "v 0 0 0"; echo "v 1 0 0"; echo "v 1 1 0"; echo "v 0 1 0"
  echo "v 0 0 1"; echo "v 1 0 1"; echo "v 1 1 1"; echo "v 0 1 1"
  echo "f 1 4 3 2"; echo "f 1 2 6 5"; echo "f 2 3 7 6"; echo "f 3 4 8 7"; echo "f 4 1 5 8"
  case "$(basename "$scan")" in holes*) ;; *) echo "f 5 6 7 8" ;; esac
} > "$out/cage.obj"
cp "$out/cage.obj" "$out/limit.obj" || exit 2
echo '{"used_method": "simplify", "limit": {"error": {"hausdorff_rel": 0.01, "hausdorff_sym_rel": 0.02, "mean_rel": 0.001}}}' \
  > "$out/report.json"
exit 0
