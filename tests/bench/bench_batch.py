#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark of batch runs (issue 28), not a test: wall time of the scan-to-cage pipeline on a fixed
subset of corpus meshes (batch_subset.txt, 40 meshes) with

  local1 / local2   cagekit.batch.run, local pool, jobs 1 / 2
  dask1 / dask2     cagekit.batch.run on a distributed LocalCluster of 1 / 2 workers, 1 thread each;
                    the workers are threads of this process (--dask-workers threads, the default, as
                    cagekit.batch's docs recommend on one machine: each scan is a child process anyway)
                    or worker processes with nannies (--dask-workers processes, as on a real cluster);
                    dask1t / dask2t and dask1p / dask2p name the kind whatever --dask-workers says.
                    Each cluster is started before the timed runs and reused
  cli1 / cli2       `cagekit batch --jobs 1 / 2` (no Python in the loop)

each repeated R times (median reported, runs interleaved so machine load hits every mode alike).
Every child runs with --threads 1 (--threads given), so 1 job vs 2 jobs measures process-level
scaling, not the SDK's own threads. Prints a markdown table, the speedups 2 jobs / 1 job, the Dask
overhead (dask2 / local2 - 1), and checks that every mode gives the same (scan, status, faces) rows
(exit 1 if not; never on timing). Targets (issue 28): speedup >= 1.7 for local and dask, Dask
overhead <= 10 %.

usage: bench_batch.py --cli build/samples/cli/cagekit [--corpus ../shared/corpus]
         [--list tests/bench/batch_subset.txt] [--repeats 3] [--modes local1,local2,dask1,dask2,cli1,cli2]
         [--faces 100] [--work /tmp/cagekit-bench-batch] [--json results.json] [--order largest|input]
         [--memory-limit MB] [--dask-workers threads|processes]
Needs CAGEKIT_LIBRARY (or an installed libcagekit) for `import cagekit`, and python3-distributed for
the dask modes.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "bindings", "python"))
os.environ["PYTHONPATH"] = os.pathsep.join([os.path.join(ROOT, "bindings", "python")] +
                                           [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])

import cagekit.batch as batch  # noqa: E402


def dask_size(mode):
    """dask2 -> 2, dask2t -> 2, dask1p -> 1; 0 when `mode` is not a dask mode."""
    digits = mode[4:].rstrip("tp")
    return int(digits) if mode.startswith("dask") and digits.isdigit() else 0


def dask_kind(mode, default):
    """'threads' or 'processes': the mode's suffix (t / p), else --dask-workers."""
    return {"t": "threads", "p": "processes"}.get(mode[-1], default)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cli", required=True)
    ap.add_argument("--corpus", default=os.path.join(ROOT, "..", "shared", "corpus"))
    ap.add_argument("--list", default=os.path.join(HERE, "batch_subset.txt"))
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--modes", default="local1,local2,dask1,dask2,cli1,cli2")
    ap.add_argument("--method", default="simplify")
    ap.add_argument("--faces", type=int, default=100)
    ap.add_argument("--timeout", type=float, default=600)
    ap.add_argument("--work", default="/tmp/cagekit-bench-batch")
    ap.add_argument("--json", default="")
    ap.add_argument("--order", default="largest", choices=["largest", "input"],
                    help="which scans start first (cagekit batch --order)")
    ap.add_argument("--memory-limit", type=int, default=0,
                    help="MiB of address space per scan (--memory-limit); the largest peak RSS is reported")
    ap.add_argument("--dask-workers", default="threads", choices=["threads", "processes"],
                    help="the LocalCluster's workers for the modes dask1 / dask2: threads of this process "
                         "(processes=False) or worker processes (processes=True)")
    a = ap.parse_args()
    cli = os.path.abspath(a.cli)
    with open(a.list) as f:
        rel = [l.strip() for l in f if l.strip() and not l.startswith("#")]
    paths = [os.path.abspath(os.path.join(a.corpus, r)) for r in rel]
    missing = [p for p in paths if not os.path.isfile(p)]
    if missing:
        print("bench_batch: %d meshes of the list are missing (first: %s): skipped" % (len(missing), missing[0]))
        return 0
    modes = a.modes.split(",")
    for m in modes:
        if not (dask_size(m) or (m.startswith("local") and m[5:].isdigit()) or (m.startswith("cli") and m[3:].isdigit())):
            ap.error("unknown mode %r (local<N>, cli<N>, dask<N>, dask<N>t, dask<N>p)" % m)
    options = {"faces": a.faces, "threads": 1}
    os.makedirs(a.work, exist_ok=True)
    listing = os.path.join(a.work, "list.txt")
    with open(listing, "w") as f:
        f.writelines(p + "\n" for p in paths)

    clusters = {}
    startup = {}
    if any(m.startswith("dask") for m in modes):
        import distributed
        for m in modes:
            if m.startswith("dask"):
                t = time.monotonic()
                cluster = distributed.LocalCluster(n_workers=dask_size(m), threads_per_worker=1,
                                                   processes=dask_kind(m, a.dask_workers) == "processes",
                                                   dashboard_address=None, silence_logs=40)
                clusters[m] = (cluster, distributed.Client(cluster))
                startup[m] = time.monotonic() - t

    def one(mode, out):
        shutil.rmtree(out, ignore_errors=True)
        t = time.monotonic()
        if mode.startswith("local"):
            rows = batch.run(paths, out, method=a.method, options=options, jobs=int(mode[5:]), timeout=a.timeout,
                             cli=cli, progress=False, order=a.order, memory_limit=a.memory_limit or None)
        elif mode.startswith("dask"):
            rows = batch.run(paths, out, method=a.method, options=options, client=clusters[mode][1],
                             timeout=a.timeout, cli=cli, progress=False, order=a.order,
                             memory_limit=a.memory_limit or None)
        else:
            subprocess.run([cli, "batch", listing, out, "--method", a.method, "--faces", str(a.faces), "--threads", "1",
                            "--jobs", mode[3:], "--timeout", str(a.timeout), "--order", a.order,
                            "--memory-limit", str(a.memory_limit), "--quiet"], check=False)
            with open(os.path.join(out, "results.json")) as f:
                rows = json.load(f)["rows"]
        seconds = time.monotonic() - t
        if hasattr(rows, "to_dict"):
            rows = rows.to_dict("records")
        peaks[mode] = max([peaks.get(mode, 0.0)] + [float(r["peak_mb"] or 0.0) for r in rows])
        return seconds, [(r["scan"], r["status"], r["faces"]) for r in rows]

    peaks = {}
    load_start = os.getloadavg()
    times = {m: [] for m in modes}
    results = {}
    for r in range(a.repeats):
        for m in modes:
            seconds, rows = one(m, os.path.join(a.work, m))
            times[m].append(seconds)
            results.setdefault(m, rows)
            print("round %d %-7s %7.2f s" % (r + 1, m, seconds), flush=True)
    load_end = os.getloadavg()
    for cluster, client in clusters.values():
        client.close()
        cluster.close()

    median = {m: statistics.median(t) for m, t in times.items()}
    reference = results[modes[0]]
    same = all(rows == reference for rows in results.values())
    ok = sum(s == "ok" for _, s, _ in reference)
    print()
    print("%d meshes (%d ok), --method %s --faces %d --threads 1, median of %d; load average %.2f at the start, "
          "%.2f at the end; %d CPUs; dask<N> modes: worker %s" % (len(paths), ok, a.method, a.faces, a.repeats,
                                                               load_start[0], load_end[0], os.cpu_count(),
                                                               a.dask_workers))
    print()
    print("| mode | median s | runs s |")
    print("|---|---|---|")
    for m in modes:
        print("| %s | %.2f | %s |" % (m, median[m], ", ".join("%.2f" % t for t in times[m])))
    print()
    summary = {}
    groups = {}  # label -> {jobs: mode}
    for m in modes:
        if m.startswith("dask"):
            groups.setdefault("dask-" + dask_kind(m, a.dask_workers), {})[dask_size(m)] = m
        else:
            kind = "local" if m.startswith("local") else "cli"
            groups.setdefault(kind, {})[int(m[len(kind):])] = m
    for label, by_jobs in groups.items():
        if 1 in by_jobs and 2 in by_jobs:
            summary[label + "_speedup"] = median[by_jobs[1]] / median[by_jobs[2]]
            print("%s: 2 jobs / 1 job speedup %.2fx (target >= 1.7)" % (label, summary[label + "_speedup"]))
    for label, by_jobs in groups.items():
        if label.startswith("dask") and 2 in by_jobs and "local2" in median:
            summary[label + "_overhead"] = median[by_jobs[2]] / median["local2"] - 1.0
            print("%s overhead: %s / local2 - 1 = %+.1f %% (target <= 10 %%)"
                  % (label, by_jobs[2], 100 * summary[label + "_overhead"]))
    for m, s in startup.items():
        print("%s: LocalCluster start-up %.2f s (not in the timed runs)" % (m, s))
    print("largest peak memory of a scan (peak_mb): %s MiB%s" % (
        ", ".join("%s %.0f" % (m, peaks[m]) for m in modes),
        "; --memory-limit %d MiB of address space per scan" % a.memory_limit if a.memory_limit else ""))
    print("order: %s; same rows (scan, status, faces) in every mode: %s" % (a.order, "yes" if same else "NO"))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(dict(meshes=len(paths), ok=ok, repeats=a.repeats, times=times, median=median, summary=summary,
                           startup=startup, load=[load_start[0], load_end[0]], cpus=os.cpu_count(), same_rows=same,
                           order=a.order, memory_limit_mb=a.memory_limit, peak_mb=peaks,
                           dask_workers=a.dask_workers),
                      f, indent=1)
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
