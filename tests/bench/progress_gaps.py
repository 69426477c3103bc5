# SPDX-License-Identifier: GPL-3.0-or-later
"""How soon can a host's cancel take effect? The largest gaps between progress reports of one
scan_to_cage call (issue 27; a benchmark, not a test).

    CAGEKIT_LIBRARY=build/sdk/capi/libcagekit.so PYTHONPATH=bindings/python /usr/bin/python3 \
        tests/bench/progress_gaps.py [--mesh ../shared/meshes/stanford-bunny.obj] [--subdivide 2] \
        [--faces 1000] [--method simplify] [--threads 0] [--top 8] [--cancel-at 0.5,3,6] [--out gaps.json]

A cancel reaches the SDK only through the progress callback (it returns False), so the longest
stretch without a report bounds how long a cancel waits. The scan is the one of
blender_responsiveness.py: the bunny, 1-to-4 midpoint-subdivided `--subdivide` times (twice:
1,111,216 triangles) with seeded Gaussian noise along the normals (sigma 1e-4 of the diagonal).
Measured: every report's time and stage; printed: the largest gaps with the stages on both sides.
With --cancel-at T,...: the call is run again for each T, cancelled at the first report at or
after T seconds, and the time from that report to the call's return is printed (the SDK's own
cancel latency: unwinding, freeing). Target (issue 27): a cancel takes effect within 0.5 s.
Never fails on timing.
"""
import argparse
import json
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "bindings", "python"))
import cagekit  # noqa: E402

ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("--mesh", default=os.path.join(os.environ.get("CAGEKIT_SHARED_MESHES") or
                                               os.path.join(ROOT, "..", "shared", "meshes"), "stanford-bunny.obj"))
ap.add_argument("--subdivide", type=int, default=2)
ap.add_argument("--faces", type=int, default=1000)
ap.add_argument("--method", default="simplify", choices=["simplify", "quad", "anisotropic"])
ap.add_argument("--threads", type=int, default=0)
ap.add_argument("--top", type=int, default=8)
ap.add_argument("--cancel-at", default="", help="comma-separated seconds: cancel runs")
ap.add_argument("--out", default=None)
ap.add_argument("--log", action="store_true", help="print the SDK's debug log with times (to attribute gaps)")
args = ap.parse_args()


def subdivide(P, F):
    """1-to-4 midpoint subdivision of a triangle mesh (as blender_responsiveness.py)."""
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    uniq, inv = np.unique(e, axis=0, return_inverse=True)
    mid = len(P) + inv.reshape(3, -1).T
    P2 = np.concatenate([P, 0.5 * (P[uniq[:, 0]] + P[uniq[:, 1]])])
    a, b, c = F[:, 0], F[:, 1], F[:, 2]
    m01, m12, m20 = mid[:, 0], mid[:, 1], mid[:, 2]
    F2 = np.concatenate([np.stack([a, m01, m20], 1), np.stack([m01, b, m12], 1),
                         np.stack([m20, m12, c], 1), np.stack([m01, m12, m20], 1)])
    return P2, F2


def make_scan():
    with cagekit.Mesh.read(args.mesh) as m:
        P, F = m.positions.astype(np.float64), np.array(m.faces, dtype=np.int64)
    for _ in range(args.subdivide):
        P, F = subdivide(P, F)
    n = np.zeros_like(P)
    fn = np.cross(P[F[:, 1]] - P[F[:, 0]], P[F[:, 2]] - P[F[:, 0]])
    for k in range(3):
        np.add.at(n, F[:, k], fn)
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)
    diag = float(np.linalg.norm(P.max(0) - P.min(0)))
    P = P + n * np.random.default_rng(1).normal(scale=1e-4 * diag, size=(len(P), 1))
    return P, F


def options():
    return dict(method=args.method, faces=args.faces,
                quad=dict(threads=args.threads), anisotropic=dict(threads=args.threads),
                fit=dict(threads=args.threads))


def run_once(P, F, cancel_at=None):
    """(reports [(t, stage, fraction)], seconds, outcome, cancel latency or None)."""
    reports = []
    t0 = [0.0]
    cancelled_at = [None]

    def progress(stage, fraction):
        t = time.perf_counter() - t0[0]
        reports.append((t, stage, fraction))
        if cancel_at is not None and t >= cancel_at and cancelled_at[0] is None:
            cancelled_at[0] = t
        return cancelled_at[0] is None

    def log(level, message):
        if args.log:
            print("  [%8.3f] %s" % (time.perf_counter() - t0[0], message), flush=True)

    with cagekit.Context(progress=progress, log=log, log_level=cagekit.LogLevel.DEBUG) as ctx:
        with cagekit.Mesh.from_arrays(P, F, context=ctx) as mesh:
            t0[0] = time.perf_counter()
            outcome = "ok"
            try:
                cage, limit, _ = cagekit.scan_to_cage(mesh, **options())
                cage.close()
                limit.close()
            except cagekit.CageKitError as e:
                outcome = "%s: %s" % (type(e).__name__, str(e)[:120])
            seconds = time.perf_counter() - t0[0]
    latency = seconds - cancelled_at[0] if cancelled_at[0] is not None else None
    return reports, seconds, outcome, latency


def largest_gaps(reports, seconds, top):
    stamps = [(0.0, "(call)", 0.0)] + reports + [(seconds, "(return)", 1.0)]
    gaps = [(b[0] - a[0], a, b) for a, b in zip(stamps, stamps[1:])]
    gaps.sort(key=lambda g: -g[0])
    return gaps[:top]


def main():
    P, F = make_scan()
    print("scan: %d vertices, %d triangles; method %s, faces %d, threads %d" %
          (len(P), len(F), args.method, args.faces, args.threads))
    reports, seconds, outcome, _ = run_once(P, F)
    print("whole call: %.2f s, %d reports, %s" % (seconds, len(reports), outcome))
    print("\n| gap s | after (t s, stage, fraction) | before |\n|---|---|---|")
    rows = []
    for g, a, b in largest_gaps(reports, seconds, args.top):
        print("| %.3f | %.2f %s %.2f | %.2f %s %.2f |" % (g, a[0], a[1], a[2], b[0], b[1], b[2]))
        rows.append(dict(gap=g, after=list(a), before=list(b)))
    cancels = []
    for text in filter(None, args.cancel_at.split(",")):
        at = float(text)
        _, s, o, latency = run_once(P, F, cancel_at=at)
        print("cancel at >= %.2f s: returned after %.2f s (%s); from the cancelling report to the return %s" %
              (at, s, o, "%.3f s" % latency if latency is not None else "-(ended before)"))
        cancels.append(dict(at=at, seconds=s, outcome=o, latency=latency))
    if args.out:
        with open(args.out, "w") as f:
            json.dump(dict(triangles=len(F), seconds=seconds, reports=len(reports), outcome=outcome,
                           largest_gaps=rows, cancels=cancels), f, indent=1)


if __name__ == "__main__":
    main()
