#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# A stand-in for the cagekit CLI in the harness's own tests (check_harness_rules.sh): each outcome
# class comes from the scan's file name, so the harness's classification and baseline rules are
# tested without running the SDK. `pipeline SCAN OUT ...` and `deform SCAN CAGE EDITED OUT ...`.
command=$1
scan=$2
case "$command" in
  pipeline)
    out=$3
    case "$(basename "$scan")" in
      crash*) kill -SEGV $$ ;;
      hang*) sleep 60; exit 0 ;;
      error*) echo "cagekit: $scan: no faces (a point cloud is not a mesh)" >&2; exit 2 ;;
      throw*) echo "cagekit: std::length_error" >&2; exit 1 ;;
      oom*) echo "cagekit: $scan: out of memory" >&2; exit 2 ;;
    esac
    mkdir -p "$out" || exit 2
    # The unit cube as a cage; holes*: without its top face (one boundary loop the scan lacks).
    {
      echo "v 0 0 0"; echo "v 1 0 0"; echo "v 1 1 0"; echo "v 0 1 0"
      echo "v 0 0 1"; echo "v 1 0 1"; echo "v 1 1 1"; echo "v 0 1 1"
      echo "f 1 4 3 2"; echo "f 1 2 6 5"; echo "f 2 3 7 6"; echo "f 3 4 8 7"; echo "f 4 1 5 8"
      case "$(basename "$scan")" in holes*) ;; *) echo "f 5 6 7 8" ;; esac
    } > "$out/cage.obj"
    echo '{"simplify": {}, "fit": {}, "limit": {"error": {"hausdorff_rel": 0.01, "hausdorff_sym_rel": 0.02, "mean_rel": 0.001}}}' \
      > "$out/report.json"
    exit 0 ;;
  deform)
    case "$(basename "$scan")" in nodeform*) echo "cagekit: deform refused" >&2; exit 2 ;; esac
    cp "$4" "$5" || exit 2
    exit 0 ;;
esac
echo "fake_cagekit: unknown command $command" >&2
exit 64
