#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""`cagekit batch` (issue 28) end to end.

usage: check_batch_cli.py CAGEKIT FAKE_PIPELINE CORPUS_DIR WORK_DIR [case...]

Cases (all by default):
  mixed      the real pipeline on a generated folder that mixes good scans with bad ones (a corrupt
             file, a point cloud, hostile sizes, an empty file) and, when CORPUS_DIR is there, the
             corpus's former crash cases: exactly the bad ones are not ok (and none of them crashes),
             the good results are complete, the tables agree with the per-scan results, --retry-failed
             runs exactly the failed ones again, and --resume
             reruns nothing (result.json and the outputs keep their modification times).
  isolation  a stand-in worker (FAKE_PIPELINE, tests/batch/fake_pipeline.sh) that raises SIGSEGV,
             sleeps past --timeout, reports out of memory, a clean error or an uncaught exception, or
             exits 0 without outputs for some scans: each of those ends only its own scan, with its
             own status; the options reach every child (--threads 1 with --jobs 2).
  interrupt  SIGTERM while scans run: the running children are killed, exit 130, the tables hold the
             finished scans only, and --resume runs exactly the unfinished ones.
  usage      --method simplify without --faces/--vertices, a mesh file as IN, an empty folder; a list
             file (comments, relative paths, names after a tab, duplicate stems).
  guard      OUT_DIR = IN_DIR with a foreign folder named like a scan: left alone, that scan fails.
  order      --order largest (the default) starts the scans by estimated work (file size over the
             format's bytes per triangle), --order input in folder order; the tables stay in input
             order; a bad --order is a usage error.
"""
import csv
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time

cli, fake, corpus, work = sys.argv[1:5]
cases = sys.argv[5:] or ["mixed", "isolation", "interrupt", "usage", "guard", "order"]
passed = failures = 0


def check(ok, name, detail=""):
    global passed, failures
    if ok:
        passed += 1
        print(f"[ OK   ] {name}", flush=True)
    else:
        failures += 1
        print(f"[ FAIL ] {name}" + (f": {detail}" if detail else ""), flush=True)


def fresh(path):
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path


def write(path, text, mode="w"):
    with open(path, mode) as f:
        f.write(text)


def sphere_off(path, rings=10, segments=20):
    pts = [(0.0, 0.0, 1.0)]
    for r in range(1, rings):
        t = math.pi * r / rings
        for k in range(segments):
            p = 2 * math.pi * k / segments
            pts.append((math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)))
    pts.append((0.0, 0.0, -1.0))
    south = len(pts) - 1
    tris = [(0, 1 + k, 1 + (k + 1) % segments) for k in range(segments)]
    for r in range(1, rings - 1):
        for k in range(segments):
            k1 = (k + 1) % segments
            a, b = 1 + (r - 1) * segments + k, 1 + (r - 1) * segments + k1
            c, d = a + segments, b + segments
            tris += [(a, c, d), (a, d, b)]
    base = 1 + (rings - 2) * segments
    tris += [(base + k, south, base + (k + 1) % segments) for k in range(segments)]
    write(path, "OFF\n%d %d 0\n" % (len(pts), len(tris)) + "".join("%.9g %.9g %.9g\n" % p for p in pts)
          + "".join("3 %d %d %d\n" % t for t in tris))


def torus_off(path, n=24, m=12, big=1.0, small=0.35):
    pts = []
    for i in range(n):
        u = 2 * math.pi * i / n
        for j in range(m):
            v = 2 * math.pi * j / m
            pts.append(((big + small * math.cos(v)) * math.cos(u), (big + small * math.cos(v)) * math.sin(u),
                        small * math.sin(v)))
    tris = []
    for i in range(n):
        for j in range(m):
            a, b = i * m + j, ((i + 1) % n) * m + j
            c, d = i * m + (j + 1) % m, ((i + 1) % n) * m + (j + 1) % m
            tris += [(a, b, d), (a, d, c)]
    write(path, "OFF\n%d %d 0\n" % (len(pts), len(tris)) + "".join("%.9g %.9g %.9g\n" % p for p in pts)
          + "".join("3 %d %d %d\n" % t for t in tris))


def batch(*args, timeout=600):
    return subprocess.run([cli, "batch", *args], capture_output=True, text=True, timeout=timeout)


def read_table(out):
    with open(os.path.join(out, "results.json")) as f:
        table = json.load(f)
    with open(os.path.join(out, "results.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    return table, rows


def mtimes(out, names, files):
    return {(n, f): os.stat(os.path.join(out, n, f)).st_mtime_ns for n in names for f in files
            if os.path.exists(os.path.join(out, n, f))}


def case_mixed():
    root = fresh(os.path.join(work, "mixed"))
    scans = fresh(os.path.join(root, "in"))
    out = os.path.join(root, "out")
    good, bad = set(), set()
    sphere_off(os.path.join(scans, "sphere.off")); good.add("sphere")
    torus_off(os.path.join(scans, "torus.off")); good.add("torus")
    # A corrupt file: a face with an index past the vertices, then garbage.
    write(os.path.join(scans, "corrupt.off"), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n#!@$%\n"); bad.add("corrupt")
    # A point cloud: vertices, no faces.
    write(os.path.join(scans, "points.ply"), "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
          "property float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"); bad.add("points")
    # Hostile sizes: headers that promise billions of elements the file does not hold.
    write(os.path.join(scans, "huge-header.off"), "OFF\n2000000000 2000000000 0\n0 0 0\n1 0 0\n"); bad.add("huge-header")
    write(os.path.join(scans, "huge-count.stl"), b"\0" * 80 + (0xFFFFFFF0).to_bytes(4, "little") + b"\0" * 50, "wb")
    bad.add("huge-count")
    write(os.path.join(scans, "empty.obj"), ""); bad.add("empty")
    # The corpus's former crash cases (simplification crashers, issue 18) and its point cloud.
    corpus_cases = {"cgal/elephant-with-holes.off": "elephant-with-holes", "cgal/couplingdown.off": "couplingdown",
                    "cgal/b9.ply": "b9"}
    if os.path.isdir(corpus):
        for rel, name in corpus_cases.items():
            shutil.copy(os.path.join(corpus, rel), scans)
            (bad if name == "b9" else good).add(name)
    else:
        print(f"mixed: the corpus folder {corpus} is absent: its crash cases are not in the folder")
    names = good | bad

    t0 = time.time()
    p = batch(scans, out, "--method", "simplify", "--faces", "60", "--jobs", "2", "--timeout", "300", "--thumbnails")
    first_seconds = time.time() - t0
    check(p.returncode == 2, "mixed: exit 2 (some scans are not ok)", f"exit {p.returncode}: {p.stderr[-2000:]}")
    summary = [l for l in p.stdout.splitlines() if l.startswith("cagekit batch: ")]
    check(len(summary) == 1 and f"{len(names)} scans: {len(good)} ok, " in summary[0],
          "mixed: one summary line with the counts", repr(p.stdout))
    check("running, ETA" in p.stderr, "mixed: progress lines (done / failed / running, ETA) on stderr", p.stderr[-500:])
    table, rows = read_table(out)
    status = {r["scan"]: r["status"] for r in table["rows"]}
    check(set(status) == names, "mixed: one row per scan", f"{sorted(status)} vs {sorted(names)}")
    check({n for n, s in status.items() if s == "ok"} == good, "mixed: exactly the good scans are ok", str(status))
    check(all(status.get(n) in ("failed", "oom") for n in bad), "mixed: every bad scan failed cleanly (no crash, "
          "no timeout)", str({n: (r["status"], r["message"]) for r in table["rows"] for n in [r["scan"]] if n in bad}))
    check(all(r["message"] for r in table["rows"] if r["status"] != "ok"), "mixed: each failure has a message")
    for r in table["rows"]:
        if r["status"] != "ok":
            continue
        d = os.path.join(out, r["scan"])
        complete = all(os.path.getsize(os.path.join(d, f)) > 0 for f in ("cage.obj", "limit.obj", "report.json",
                                                                             "result.json"))
        with open(os.path.join(d, "report.json")) as f:
            report = json.load(f)
        check(complete and r["faces"] and r["faces"] > 0 and isinstance(r["two_sided_error"], float)
              and r["two_sided_error"] == report["limit"]["error"]["hausdorff_sym_rel"] and r["seconds"] > 0
              and r["peak_mb"] > 0, f"mixed: {r['scan']}: complete outputs, faces, two-sided error, time, memory",
              json.dumps(r))
    # Thumbnails where the render module can draw here (a probe render of one good scan's cage).
    probe = subprocess.run([cli, "render", os.path.join(root, "probe.png"), "--cage",
                            os.path.join(out, "sphere", "cage.obj"), "--quiet"], capture_output=True, text=True)
    if probe.returncode == 0:
        check(all((r["thumbnail"] == "thumbnail.png") == (r["status"] == "ok") for r in table["rows"]) and
              all(os.path.getsize(os.path.join(out, n, "thumbnail.png")) > 1000 for n in good),
              "mixed: --thumbnails: a thumbnail.png for each ok scan, none for the others")
    else:
        print(f"mixed: no thumbnails expected here (render: {probe.stderr.strip()})")
        check(all(r["thumbnail"] == "" for r in table["rows"]), "mixed: --thumbnails without a renderer: none, "
              "and the statuses do not change")
    check(table["summary"]["ok"] == len(good) and table["summary"]["scans"] == len(names)
          and table["summary"]["resumed"] == 0, "mixed: results.json summary", json.dumps(table["summary"]))
    check([(r["scan"], r["status"]) for r in rows] == [(r["scan"], r["status"]) for r in table["rows"]],
          "mixed: results.csv has the rows of results.json")
    for r in table["rows"]:
        with open(os.path.join(out, r["scan"], "result.json")) as f:
            own = json.load(f)
        if own["status"] != r["status"] or own["options"] != ["--method", "simplify", "--faces", "60"]:
            check(False, f"mixed: {r['scan']}/result.json matches its row", json.dumps(own))
            break
    else:
        check(True, "mixed: each scan's result.json matches its row and names the options")
    check(not [f for f in os.listdir(out) if f.endswith(".tmp")], "mixed: no temporary files left")

    # --resume: nothing runs again.
    before = mtimes(out, names, ("result.json", "cage.obj", "pipeline.stderr"))
    t0 = time.time()
    p = batch(scans, out, "--method", "simplify", "--faces", "60", "--jobs", "2", "--resume")
    resume_seconds = time.time() - t0
    table2, _ = read_table(out)
    check(p.returncode == 2 and all(r["resumed"] for r in table2["rows"]) and table2["summary"]["resumed"] == len(names),
          "resume: every scan resumed", f"exit {p.returncode} {p.stderr[-500:]}")
    check(mtimes(out, names, ("result.json", "cage.obj", "pipeline.stderr")) == before,
          "resume: no result or output was written again (modification times)")
    check([(r["scan"], r["status"], r["faces"]) for r in table2["rows"]] ==
          [(r["scan"], r["status"], r["faces"]) for r in table["rows"]], "resume: the same table")
    print(f"mixed: first run {first_seconds:.1f} s, resumed run {resume_seconds:.2f} s")

    # --retry-failed: exactly the scans that were not ok run again; the ok ones are kept as they are.
    failed_before = {r["scan"] for r in table2["rows"] if r["status"] != "ok"}
    p = batch(scans, out, "--method", "simplify", "--faces", "60", "--jobs", "2", "--retry-failed")
    table3, _ = read_table(out)
    resumed3 = {r["scan"] for r in table3["rows"] if r["resumed"]}
    after = mtimes(out, names, ("result.json",))
    rewritten = {n for n in names if after.get((n, "result.json")) != before.get((n, "result.json"))}
    check(p.returncode == 2 and failed_before == bad and resumed3 == good and rewritten == bad
          and table3["summary"]["retried"] == len(bad) and table3["summary"]["resumed"] == len(good)
          and "failed before, run again" in p.stdout,
          "retry-failed: the failed scans ran again (their result.json rewritten), the ok ones were kept",
          f"exit {p.returncode}; resumed {sorted(resumed3)}; rewritten {sorted(rewritten)}; {json.dumps(table3['summary'])}")
    check([(r["scan"], r["status"], r["faces"]) for r in table3["rows"]] ==
          [(r["scan"], r["status"], r["faces"]) for r in table["rows"]], "retry-failed: the same statuses again")

    # --memory-limit: a limit far below what a scan needs ends it as oom (not as a crash), with a message.
    p = batch(scans, os.path.join(root, "small"),
              "--faces", "60", "--memory-limit", "24", "--quiet")
    table3, _ = read_table(os.path.join(root, "small"))
    check(p.returncode == 2 and all(r["status"] == "oom" and r["message"] for r in table3["rows"]),
          "memory limit: every scan under 24 MiB ends as oom with a message",
          str({r["scan"]: (r["status"], r["message"]) for r in table3["rows"] if r["status"] != "oom"}))


def case_isolation():
    root = fresh(os.path.join(work, "isolation"))
    scans = fresh(os.path.join(root, "in"))
    out = os.path.join(root, "out")
    # The stand-in's outcome comes from the file name; a wrapper records each child's arguments.
    expected = {"ok1": "ok", "crash": "crash", "hang": "timeout", "oom": "oom", "error": "failed", "ok2": "ok",
                "holes-ok3": "ok", "throw": "crash", "nooutput": "failed"}
    for name in expected:
        write(os.path.join(scans, name + ".off"), "OFF\n0 0 0\n")
    env = dict(os.environ, CAGEKIT_BATCH_WORKER=f"sh {fake}")
    t0 = time.time()
    p = subprocess.run([cli, "batch", scans, out, "--method", "quad", "--faces", "40", "--no-fallback", "--jobs", "2",
                        "--timeout", "2"], capture_output=True, text=True, env=env, timeout=120)
    took = time.time() - t0
    table, _ = read_table(out)
    got = {r["scan"]: r for r in table["rows"]}
    check({n: r["status"] for n, r in got.items()} == expected, "isolation: each scan's own status",
          str({n: (r["status"], r["message"]) for n, r in got.items()}))
    check("SIGSEGV" in got["crash"]["message"], "isolation: the crash names SIGSEGV", got["crash"]["message"])
    check(got["throw"]["message"] == "exit 1: std::length_error" and "no cage.obj" not in got["nooutput"]["message"]
          and got["nooutput"]["message"].startswith("exit 0 but report.json"),
          "isolation: an uncaught exception is a crash; exit 0 without outputs is a failure",
          f'{got["throw"]["message"]} | {got["nooutput"]["message"]}')
    check(2.0 <= got["hang"]["seconds"] < 10.0 and took < 30, "isolation: the sleeping child was killed at the "
          "timeout", f"{got['hang']['seconds']} s, batch {took:.1f} s")
    check(got["ok1"]["faces"] == 6 and got["holes-ok3"]["faces"] == 5 and got["ok1"]["two_sided_error"] == 0.02,
          "isolation: the ok scans' faces (from cage.obj) and error (from report.json)", json.dumps(got["ok1"]))
    check(not os.path.exists(os.path.join(out, "hang", "result.json")) or got["hang"]["status"] == "timeout",
          "isolation: the timeout's result says timeout")
    with open(os.path.join(out, "ok1", "argv.txt")) as f:
        argv = f.read().split("\n")[:-1]
    scan_path = os.path.join(scans, "ok1.off")
    check(argv == [scan_path, os.path.join(out, "ok1"), "--method", "quad", "--faces", "40", "--no-fallback",
                   "--threads", "1", "--quiet"],
          "isolation: the child gets SCAN OUTDIR, the pipeline options given, --threads 1 (jobs 2), --quiet", str(argv))

    # --threads given: forwarded as it is; --jobs 1: no --threads added. Options changed: --resume reruns.
    p = subprocess.run([cli, "batch", scans, out, "--method", "quad", "--faces", "40", "--jobs", "1", "--timeout", "2",
                        "--resume"], capture_output=True, text=True, env=env, timeout=120)
    table2, _ = read_table(out)
    with open(os.path.join(out, "ok1", "argv.txt")) as f:
        argv = f.read().split("\n")[:-1]
    check(not any(r["resumed"] for r in table2["rows"]) and "--threads" not in argv,
          "isolation: other options: --resume runs the scans again; --jobs 1 adds no --threads", str(argv))
    p = subprocess.run([cli, "batch", scans, out, "--method", "quad", "--faces", "40", "--jobs", "2", "--threads", "3",
                        "--timeout", "2", "--json", "--quiet"], capture_output=True, text=True, env=env, timeout=120)
    with open(os.path.join(out, "ok1", "argv.txt")) as f:
        argv = f.read().split("\n")[:-1]
    check(argv.count("--threads") == 1 and argv[argv.index("--threads") + 1] == "3",
          "isolation: --threads given: forwarded, no --threads 1", str(argv))
    check(json.loads(p.stdout)["summary"]["scans"] == len(expected) and p.stderr == "",
          "isolation: --json prints results.json on stdout; --quiet: nothing on stderr", p.stderr[-300:])


def case_interrupt():
    root = fresh(os.path.join(work, "interrupt"))
    scans = fresh(os.path.join(root, "in"))
    out = os.path.join(root, "out")
    for name in ("a-ok", "b-ok", "hang1", "hang2", "z-ok"):
        write(os.path.join(scans, name + ".off"), "OFF\n0 0 0\n")
    env = dict(os.environ, CAGEKIT_BATCH_WORKER=f"sh {fake}")
    p = subprocess.Popen([cli, "batch", scans, out, "--faces", "10", "--jobs", "2"], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, env=env)
    deadline = time.time() + 30
    while time.time() < deadline and not (os.path.isdir(os.path.join(out, "hang1")) and
                                          os.path.isdir(os.path.join(out, "hang2"))):
        time.sleep(0.05)
    time.sleep(0.3)
    t0 = time.time()
    p.send_signal(signal.SIGTERM)
    try:
        stdout, stderr = p.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        p.kill()
        stdout, stderr = p.communicate()
    check(p.returncode == 130 and time.time() - t0 < 10, "interrupt: SIGTERM ends the batch quickly, exit 130",
          f"exit {p.returncode}: {stderr[-500:]}")
    table, _ = read_table(out)
    done = {r["scan"] for r in table["rows"]}
    check(done == {"a-ok", "b-ok"} and table["summary"]["not_run"] == 3 and "not run" in stdout,
          "interrupt: the tables hold the finished scans, the rest counted as not run", f"{done} {stdout}")
    check(not os.path.exists(os.path.join(out, "hang1", "result.json")), "interrupt: a killed scan has no result")
    leftovers = subprocess.run(["pgrep", "-f", f"{scans}/hang"], capture_output=True, text=True).stdout.split()
    check(not leftovers, "interrupt: no child left running", str(leftovers))
    # --resume runs the unfinished ones only (the hangs now time out).
    p = subprocess.run([cli, "batch", scans, out, "--faces", "10", "--jobs", "2", "--resume", "--timeout", "1"],
                       capture_output=True, text=True, env=env, timeout=60)
    table, _ = read_table(out)
    got = {r["scan"]: (r["status"], r["resumed"]) for r in table["rows"]}
    check(got == {"a-ok": ("ok", True), "b-ok": ("ok", True), "hang1": ("timeout", False),
                  "hang2": ("timeout", False), "z-ok": ("ok", False)}, "interrupt: --resume runs only the rest",
          str(got))


def case_usage():
    root = fresh(os.path.join(work, "usage"))
    empty = fresh(os.path.join(root, "empty"))
    sphere_off(os.path.join(root, "one.off"))
    p = batch(empty, os.path.join(root, "out"), "--faces", "10")
    check(p.returncode == 2 and "no scans" in p.stderr, "usage: an empty folder is bad input (exit 2)", p.stderr)
    p = batch(os.path.join(root, "one.off"), os.path.join(root, "out"), "--faces", "10")
    check(p.returncode == 2 and "list file" in p.stderr, "usage: a mesh file as IN is bad input (exit 2)", p.stderr)
    p = batch(empty, os.path.join(root, "out"))
    check(p.returncode == 64 and "--faces" in p.stderr, "usage: --method simplify needs --faces or --vertices (64)",
          p.stderr)
    # A list: comments, relative paths (to the list's folder), a name after a tab, duplicate stems.
    sub = fresh(os.path.join(root, "sub"))
    sphere_off(os.path.join(sub, "one.off"))
    write(os.path.join(root, "list.txt"), "# scans\none.off\n\nsub/one.off\n%s\tnamed\n" % os.path.join(sub, "one.off"))
    env = dict(os.environ, CAGEKIT_BATCH_WORKER=f"sh {fake}")
    p = subprocess.run([cli, "batch", os.path.join(root, "list.txt"), os.path.join(root, "out"), "--faces", "10"],
                       capture_output=True, text=True, env=env, timeout=60)
    table, _ = read_table(os.path.join(root, "out"))
    got = [(r["scan"], r["file"], r["status"]) for r in table["rows"]]
    check(p.returncode == 0 and got == [("one", os.path.join(root, "one.off"), "ok"),
                                        ("one.off", os.path.join(root, "sub/one.off"), "ok"),
                                        ("named", os.path.join(sub, "one.off"), "ok")],
          "list: comments skipped, paths relative to the list, unique folder names, names after a tab", str(got))


def case_guard():
    # OUT_DIR = IN_DIR, where a folder has a scan's name: it is left alone, that scan fails, the others run.
    # The worker through the hidden --worker option this time.
    root = fresh(os.path.join(work, "guard"))
    for name in ("x", "y"):
        write(os.path.join(root, name + ".off"), "OFF\n0 0 0\n")
    os.makedirs(os.path.join(root, "x"))
    write(os.path.join(root, "x", "keep.txt"), "user data\n")
    p = batch(root, root, "--faces", "10", "--worker", f"sh {fake}")
    table, _ = read_table(root)
    got = {r["scan"]: (r["status"], r["message"]) for r in table["rows"]}
    check(p.returncode == 2 and got["y"][0] == "ok" and got["x"][0] == "failed" and "left as it is" in got["x"][1]
          and os.path.isfile(os.path.join(root, "x", "keep.txt")) and not os.path.exists(os.path.join(root, "x",
                                                                                                       "result.json")),
          "guard: a folder not made by cagekit batch is left alone (its scan fails); --worker runs the stand-in",
          str(got))


def case_order():
    # One job, the stand-in worker: the children run one after another, so the modification times of
    # their argv.txt give the order in which the scans started.
    root = fresh(os.path.join(work, "order"))
    scans = fresh(os.path.join(root, "in"))
    # Estimated triangles: a 100/45, b 9000/45 = 200, c (binary STL, 84 + 50 * 60) 60,
    # d (ASCII STL, "solid" and not 84 + 50k bytes) 2000/250 = 8, e (Draco) 300/3 = 100.
    write(os.path.join(scans, "a.off"), "OFF\n" + "#" * 95)
    write(os.path.join(scans, "b.off"), "OFF\n" + "#" * 8995)
    write(os.path.join(scans, "c.stl"), b"\0" * (84 + 50 * 60), "wb")
    write(os.path.join(scans, "d.stl"), "solid d\n" + "#" * 1992)
    write(os.path.join(scans, "e.drc"), b"\1" * 300, "wb")
    env = dict(os.environ, CAGEKIT_BATCH_WORKER=f"sh {fake}")

    def started(order):
        out = fresh(os.path.join(root, "out-" + (order or "default")))
        args = [cli, "batch", scans, out, "--faces", "10", "--jobs", "1", "--quiet"] + (["--order", order] if order
                                                                                        else [])
        p = subprocess.run(args, capture_output=True, text=True, env=env, timeout=120)
        table, _ = read_table(out)
        times = {r["scan"]: os.stat(os.path.join(out, r["scan"], "argv.txt")).st_mtime_ns for r in table["rows"]}
        return p, table, sorted(times, key=times.get)

    p, table, first = started(None)
    check(p.returncode == 0 and first == ["b", "e", "c", "d", "a"] and table["order"] == "largest",
          "order: by default the scans start by estimated work", f"{first} {p.returncode} {p.stderr[-300:]}")
    check([r["scan"] for r in table["rows"]] == ["a", "b", "c", "d", "e"], "order: the table stays in input order",
          str([r["scan"] for r in table["rows"]]))
    p, table, first = started("input")
    check(p.returncode == 0 and first == ["a", "b", "c", "d", "e"] and table["order"] == "input",
          "order: --order input starts them in folder order", str(first))
    p = batch(scans, os.path.join(root, "out-bad"), "--faces", "10", "--order", "smallest")
    check(p.returncode != 0 and "--order" in p.stderr, "order: a bad --order is a usage error", p.stderr[-300:])


for case in cases:
    {"mixed": case_mixed, "isolation": case_isolation, "interrupt": case_interrupt, "usage": case_usage,
     "guard": case_guard, "order": case_order}[case]()
print(f"{passed} passed, {failures} failed")
sys.exit(1 if failures else 0)
