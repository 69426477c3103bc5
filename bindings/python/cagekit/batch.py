# SPDX-License-Identifier: GPL-3.0-or-later
"""cagekit.batch: the scan-to-cage pipeline on many scans, on this machine or on a Dask cluster.

    import cagekit.batch
    table = cagekit.batch.run(["a.off", "b.stl"], "out", method="simplify", options={"faces": 300})
    table = cagekit.batch.run("scans/", "out", method="quad", client=distributed.Client("tcp://sched:8786"))

On one machine, a LocalCluster of worker threads (LocalCluster(n_workers=N, threads_per_worker=1,
processes=False)) is the one to use: each scan is its own child process already, so worker
processes only add overhead (tests/bench/RESULTS.md, "Batch").

Every scan runs in its own child process: `cagekit batch` of that one scan (so its own child
`cagekit pipeline`, under the time and memory limits), on this machine (client=None: a local pool
of `jobs` threads, each waiting on its child) or on a worker of a `distributed.Client` (one task
per scan). A crash, a timeout or an out-of-memory therefore marks only that scan; Dask itself
cannot kill a task that runs in its worker's process. The rows are the CLI's (`cagekit batch
--help`): file, scan, status (ok, failed, timeout, crash, oom), message, seconds, peak_mb, faces,
two_sided_error, scan_to_limit, limit_to_scan, used_method, fallback, ended, thumbnail, resumed.
OUT_DIR/<scan>/ holds each scan's outputs and result.json (written last), OUT_DIR/results.csv and
results.json the table, as `cagekit batch` writes them.

The `cagekit` executable is the `cli` argument, else $CAGEKIT_CLI, else the CLI the wheel bundles
(cagekit/bin/cagekit), else `cagekit` on PATH; on a cluster it is looked up on each worker, so
workers with the wheel installed need nothing else. Pure Python (standard library; `distributed` only when a
client is given, pandas only when importable).
"""
import concurrent.futures
import csv
import io
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import uuid

from . import _cli

__all__ = ["run", "run_scan", "find_cli", "scan_names", "cli_arguments", "estimated_work", "COLUMNS", "STATUSES"]

MESH_EXTENSIONS = (".off", ".obj", ".ply", ".stl", ".drc")
STATUSES = ("ok", "failed", "timeout", "crash", "oom")
COLUMNS = ("file", "scan", "status", "message", "seconds", "peak_mb", "faces", "two_sided_error", "scan_to_limit",
           "limit_to_scan", "used_method", "fallback", "ended", "thumbnail", "resumed")
# Statuses a retry may change (a clean failure is the same every time).
_RETRIED = ("crash", "timeout", "oom")
# The margin a task gives its `cagekit batch` child past the scan's own --timeout before it stops it.
_GRACE_SECONDS = 60.0


def find_cli(cli=None):
    """The `cagekit` executable: `cli`, else $CAGEKIT_CLI, else the CLI bundled in this package (the
    wheel's cagekit/bin/cagekit), else `cagekit` on PATH (FileNotFoundError)."""
    candidate = cli or os.environ.get("CAGEKIT_CLI") or _cli.bundled_cli() or shutil.which("cagekit")
    if not candidate:
        raise FileNotFoundError("cagekit.batch: no cagekit executable: pass cli=, set CAGEKIT_CLI, install the wheel "
                                "(it bundles the CLI) or put cagekit on PATH")
    if os.sep not in candidate:
        found = shutil.which(candidate)
        if not found:
            raise FileNotFoundError("cagekit.batch: %r is not on PATH" % candidate)
        candidate = found
    if not (os.path.isfile(candidate) and os.access(candidate, os.X_OK)):
        raise FileNotFoundError("cagekit.batch: %s is not an executable file" % candidate)
    return candidate


def _expand(paths):
    """A folder (its mesh files, sorted), a list file (one path a line, '#' comments, relative to the
    list's folder, optional TAB name), a mesh file, or an iterable of paths -> [(path, name or None)]."""
    if isinstance(paths, (str, bytes, os.PathLike)):
        root = os.fsdecode(paths)
        if os.path.isdir(root):
            return [(os.path.join(root, f), None) for f in sorted(os.listdir(root))
                    if os.path.isfile(os.path.join(root, f)) and os.path.splitext(f)[1].lower() in MESH_EXTENSIONS]
        if os.path.splitext(root)[1].lower() in MESH_EXTENSIONS:
            return [(root, None)]
        entries = []
        base = os.path.dirname(root)
        with open(root, encoding="utf-8") as f:
            for line in f:
                line = line.rstrip("\r\n")
                name = None
                if "\t" in line:
                    line, name = line.split("\t", 1)
                    name = name.strip() or None
                line = line.strip()
                if not line or line.startswith("#"):
                    continue
                entries.append((line if os.path.isabs(line) or not base else os.path.join(base, line), name))
        return entries
    return [(os.fspath(p), None) for p in paths]


def _clean(name):
    name = "".join("_" if c in "/\\" or ord(c) < 32 else c for c in name)
    return "scan" if name in ("", ".", "..") else name


def scan_names(paths):
    """Each scan's output folder name, as `cagekit batch` picks it: the file's stem, made unique in
    input order (then the file name, then stem-2, stem-3, ...). `paths`: [(path, requested name or None)]
    or plain paths."""
    taken = {"results.csv", "results.json", "results.csv.tmp", "results.json.tmp"}
    names = []
    for entry in paths:
        path, requested = entry if isinstance(entry, tuple) else (entry, None)
        if requested:
            name = _clean(requested)
            if name in taken:
                raise ValueError("cagekit.batch: the scan name %r is used twice" % requested)
        else:
            base = os.path.basename(path)
            stem = os.path.splitext(base)[0]
            name = _clean(stem)
            if name in taken:
                name = _clean(base)
            k = 2
            while name in taken:
                name = "%s-%d" % (_clean(stem), k)
                k += 1
        taken.add(name)
        names.append(name)
    return names


def cli_arguments(method="simplify", options=None):
    """The pipeline options as `cagekit batch` arguments: {"faces": 300, "fit_tolerance": 1e-4,
    "no_repair": True} -> ["--method", "simplify", "--faces", "300", ...]. Keys with or without the
    leading '--', '_' read as '-'; True: a flag; False or None: left out; a list: the option repeated."""
    arguments = ["--method", str(method)]
    for key, value in (options or {}).items():
        name = key if key.startswith("--") else "--" + key.replace("_", "-")
        if name in ("--method", "--jobs", "--timeout", "--memory-limit", "--resume", "--json", "--quiet"):
            raise ValueError("cagekit.batch: %s is an argument of run(), not a pipeline option" % name)
        if value is None or value is False:
            continue
        if value is True:
            arguments.append(name)
        elif isinstance(value, (list, tuple)):
            for v in value:
                arguments += [name, str(v)]
        else:
            arguments += [name, str(value)]
    return arguments


def _write_atomic(path, data):
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode("utf-8"))
    os.replace(tmp, path)


def _stop(process):
    """SIGTERM to the child's session (the batch kills its pipeline child and exits), then SIGKILL."""
    for sig, wait in ((signal.SIGTERM, 15.0), (signal.SIGKILL, 15.0)):
        try:
            os.killpg(process.pid, sig)
        except ProcessLookupError:
            pass
        try:
            return process.communicate(timeout=wait)
        except subprocess.TimeoutExpired:
            continue
    return process.communicate()


def _row_from_result(result, path, name):
    row = {k: result.get(k) for k in COLUMNS}
    row["file"], row["scan"], row["resumed"] = path, name, False
    return row


def _failed_row(path, name, status, message, seconds=0.0):
    row = dict.fromkeys(COLUMNS)
    row.update(file=path, scan=name, status=status, message=message, seconds=round(seconds, 3), peak_mb=0.0,
               ended="", thumbnail="", resumed=False)
    return row


def _one_attempt(cli, path, name, arguments, timeout, memory_limit, data, work):
    """`cagekit batch` of one scan in `work`; returns (row, folder of its outputs or None)."""
    scan_path = path
    if data is not None:  # bytes: the scan travels with the task
        os.makedirs(os.path.join(work, "input"), exist_ok=True)
        scan_path = os.path.join(work, "input", os.path.basename(path) or "scan.off")
        with open(scan_path, "wb") as f:
            f.write(data)
    scan_path = os.path.abspath(scan_path)
    listing = os.path.join(work, "list.txt")
    with open(listing, "w", encoding="utf-8") as f:
        f.write("%s\t%s\n" % (scan_path, name))
    out = os.path.join(work, "out")
    command = [cli, "batch", listing, out, *arguments, "--jobs", "1", "--quiet"]
    if timeout:
        command += ["--timeout", repr(float(timeout))]
    if memory_limit:
        command += ["--memory-limit", str(int(memory_limit))]
    start = time.monotonic()
    process = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                               start_new_session=True)
    try:
        _, err = process.communicate(timeout=(float(timeout) + _GRACE_SECONDS) if timeout else None)
    except subprocess.TimeoutExpired:
        _stop(process)
        return _failed_row(path, name, "timeout", "cagekit batch did not end within the timeout",
                           time.monotonic() - start), None
    except BaseException:
        _stop(process)
        raise
    folder = os.path.join(out, name)
    text = err.decode("utf-8", "replace").strip().splitlines()
    if process.returncode == 64:  # usage: the arguments are wrong for every scan
        raise ValueError("cagekit.batch: %s" % (text[0] if text else "cagekit batch: usage error (exit 64)"))
    try:
        with open(os.path.join(folder, "result.json"), encoding="utf-8") as f:
            result = json.load(f)
    except (OSError, ValueError):
        why = text[0] if text else "no message"
        code = process.returncode
        what = "signal %d" % -code if code < 0 else "exit %d" % code
        return _failed_row(path, name, "crash", "cagekit batch %s without a result: %s" % (what, why),
                           time.monotonic() - start), None
    return _row_from_result(result, path, name), folder


def run_scan(path, name, arguments, cli=None, timeout=None, memory_limit=None, data=None, out_dir=None, retries=0):
    """One scan through a child `cagekit batch` (in a temporary folder on this machine); the task of
    run(). Returns (row, files): with `out_dir` (storage this machine shares with the caller) the
    scan's outputs are moved to out_dir/<name>/ (result.json last) and files is None; without it,
    files maps each output's name to its bytes. `data`: the scan's bytes (no shared storage); `path`
    then only names it. A crash, timeout or out-of-memory is retried up to `retries` times."""
    cli = find_cli(cli)
    attempt = 0
    while True:
        work = tempfile.mkdtemp(prefix="cagekit-batch-")
        try:
            row, folder = _one_attempt(cli, path, name, arguments, timeout, memory_limit, data, work)
            if row["status"] in _RETRIED and attempt < retries:
                attempt += 1
                continue
            row["attempts"] = attempt + 1
            files = None
            if folder is not None:
                with open(os.path.join(folder, "result.json"), encoding="utf-8") as f:
                    result = json.load(f)
                result["file"] = path  # as the caller named it (bytes: not the temporary copy)
                result_text = json.dumps(result) + "\n"
                if out_dir is not None:
                    _place(out_dir, name, folder, result_text)
                else:
                    files = {}
                    for entry in sorted(os.listdir(folder)):
                        if entry != "result.json" and os.path.isfile(os.path.join(folder, entry)):
                            with open(os.path.join(folder, entry), "rb") as f:
                                files[entry] = f.read()
                    files["result.json"] = result_text.encode("utf-8")
            return row, files
        finally:
            shutil.rmtree(work, ignore_errors=True)


def _ours_or_absent(target):
    """Whether out_dir/<name> may be replaced: absent, empty, or an earlier run's scan folder (the CLI's rule)."""
    if not os.path.lexists(target):
        return True
    if os.path.islink(target) or not os.path.isdir(target):
        return False
    return not os.listdir(target) or any(os.path.exists(os.path.join(target, m))
                                         for m in ("result.json", "pipeline.stderr", "pipeline.stdout"))


def _replace_folder(target):
    if not _ours_or_absent(target):
        raise FileExistsError("%s exists and is not a scan folder of cagekit batch: left as it is" % target)
    shutil.rmtree(target, ignore_errors=True)
    os.makedirs(target)


def _place(out_dir, name, folder, result_text):
    """Moves a finished scan's outputs to out_dir/<name>/, result.json last (atomic rename)."""
    target = os.path.join(out_dir, name)
    _replace_folder(target)
    for entry in sorted(os.listdir(folder)):
        if entry != "result.json":
            shutil.move(os.path.join(folder, entry), os.path.join(target, entry))
    _write_atomic(os.path.join(target, "result.json"), result_text)


def _write_files(out_dir, name, files):
    target = os.path.join(out_dir, name)
    _replace_folder(target)
    for entry, content in files.items():
        if entry != "result.json":
            _write_atomic(os.path.join(target, entry), content)
    if "result.json" in files:
        _write_atomic(os.path.join(target, "result.json"), files["result.json"])


def _option_pairs(words):
    """Options as sorted (name, value) pairs ("" for a flag), as the CLI compares them."""
    pairs, k = [], 0
    while k < len(words):
        if k + 1 < len(words) and not words[k + 1].startswith("--"):
            pairs.append((words[k], words[k + 1]))
            k += 2
        else:
            pairs.append((words[k], ""))
            k += 1
    return sorted(pairs)


def _earlier(out_dir, path, name, arguments):
    """The earlier result of a scan that `resume` may keep (the CLI's rule: the same file, made with the
    same pipeline options, in any order)."""
    try:
        with open(os.path.join(out_dir, name, "result.json"), encoding="utf-8") as f:
            result = json.load(f)
    except (OSError, ValueError):
        return None
    if (result.get("file") != path or not isinstance(result.get("options"), list) or not result.get("status")
            or _option_pairs(result["options"]) != _option_pairs(arguments)):
        return None
    row = _row_from_result(result, path, name)
    row["resumed"] = True
    return row


class _ConsoleBar:
    """A one-line bar on stderr: a redrawn line on a terminal, else a line at each tenth."""

    def __init__(self, total, enabled):
        self.total, self.enabled, self.done, self.failed = total, enabled and total > 0, 0, 0
        self.terminal = sys.stderr.isatty()
        self.start = time.monotonic()
        self.lock = threading.Lock()
        self.last_tenth = -1

    def update(self, row):
        with self.lock:
            self.done += 1
            self.failed += row["status"] != "ok"
            if not self.enabled:
                return
            elapsed = time.monotonic() - self.start
            eta = elapsed / self.done * (self.total - self.done)
            width = 30
            filled = int(width * self.done / self.total)
            line = "cagekit.batch [%s%s] %d/%d, %d failed, ETA %ds" % ("#" * filled, "-" * (width - filled), self.done,
                                                                      self.total, self.failed, int(eta + 0.5))
            if self.terminal:
                sys.stderr.write("\r" + line + ("\n" if self.done == self.total else ""))
                sys.stderr.flush()
            elif self.done * 10 // self.total != self.last_tenth:
                self.last_tenth = self.done * 10 // self.total
                sys.stderr.write(line + "\n")


def _csv_number(value, digits):
    return "" if value is None else ("%." + digits) % value


def _write_tables(out_dir, rows, meta):
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(COLUMNS)
    for r in rows:
        fallback = r.get("fallback")
        writer.writerow([r["file"], r["scan"], r["status"], r.get("message") or "",
                         _csv_number(r.get("seconds"), "3f"), _csv_number(r.get("peak_mb"), "1f"),
                         _csv_number(r.get("faces"), "0f"), _csv_number(r.get("two_sided_error"), "6g"),
                         _csv_number(r.get("scan_to_limit"), "6g"), _csv_number(r.get("limit_to_scan"), "6g"),
                         r.get("used_method") or "", "" if fallback is None else str(bool(fallback)).lower(),
                         r.get("ended") or "", r.get("thumbnail") or "", str(bool(r.get("resumed"))).lower()])
    _write_atomic(os.path.join(out_dir, "results.csv"), out.getvalue())
    summary = {s: sum(r["status"] == s for r in rows) for s in STATUSES}
    summary = dict(scans=len(rows), **summary, resumed=sum(bool(r.get("resumed")) for r in rows),
                   seconds=round(meta.pop("seconds"), 3))
    table = dict(format="cagekit-batch/1", **meta, summary=summary, rows=[{k: r.get(k) for k in COLUMNS} for r in rows])
    _write_atomic(os.path.join(out_dir, "results.json"), json.dumps(table, indent=1) + "\n")
    return summary


def estimated_work(path):
    """A scan's estimated work, as `cagekit batch --order largest` takes it: the file's size over its
    format's typical bytes per triangle (binary STL 50, ASCII STL ~250, OFF/OBJ ~45, PLY ~25, Draco
    ~3). 0 for a file that cannot be read. Only the order in which scans start depends on it."""
    try:
        size = os.path.getsize(path)
    except OSError:
        return 0.0
    ext = os.path.splitext(os.fspath(path))[1].lower()
    per_face = 45.0
    if ext == ".stl":
        try:
            with open(path, "rb") as f:
                head = f.read(5)
        except OSError:
            head = b""
        per_face = 250.0 if head == b"solid" and size % 50 != 84 % 50 else 50.0
    elif ext == ".ply":
        per_face = 25.0
    elif ext == ".drc":
        per_face = 3.0
    return size / per_face


def _host(address):
    """The machine of a worker address: tcp://10.0.0.5:40123 -> 10.0.0.5, tls://[::1]:40123 -> [::1];
    inproc://192.0.2.2/14463/4 (a LocalCluster with processes=False: threads of one process) -> 192.0.2.2."""
    rest = address.split("://", 1)[-1]
    if address.startswith("inproc://"):
        return rest.split("/", 1)[0]
    return rest.rsplit(":", 1)[0]


def _per_host_threads(client):
    """The most worker threads on one machine (> 1: scans run side by side there, so --threads 1 each)."""
    hosts = {}
    for address, n in client.nthreads().items():
        host = _host(address)
        hosts[host] = hosts.get(host, 0) + n
    return max(hosts.values()) if hosts else 1


def run(paths, out_dir, method="simplify", options=None, client=None, jobs=None, timeout=None, retries=0, cli=None,
        memory_limit=None, transfer="paths", resume=False, retry_failed=False, progress=True, thumbnails=False,
        order="largest"):
    """Runs the pipeline on every scan and returns the results table (one row per scan, in input order):
    a pandas DataFrame when pandas is importable, else a list of dicts (COLUMNS, plus "attempts").

    paths: an iterable of mesh paths, a folder (its .off .obj .ply .stl .drc files) or a list file (as
    `cagekit batch` reads it). out_dir: OUT_DIR (created), as in `cagekit batch`. method: simplify,
    quad or anisotropic. options: the pipeline's options, {CLI option name: value} (see
    cli_arguments; simplify needs "faces" or "vertices"). client: None (a local pool of `jobs` child
    processes, default the CPU count) or a distributed.Client (one task per scan on its workers).
    Unless options give "threads", each child runs with --threads 1 when several run at once on one
    machine. timeout: seconds per scan (None: none); memory_limit: MiB of address space per scan;
    retries: how often a crash, timeout or out-of-memory is tried again (with a client, also a task
    whose worker died). transfer: "paths" (every worker sees the scans and out_dir at the same paths)
    or "bytes" (scans and outputs travel with the tasks; this process writes out_dir). resume: keep
    the scans with a result made with the same options. retry_failed: resume, except that the scans
    whose earlier result is not ok run again (`cagekit batch --retry-failed`). progress: distributed.progress with a client,
    else a console bar on stderr. thumbnails: OUT_DIR/<scan>/thumbnail.png for each ok scan. order:
    which scans start first, "largest" (by estimated_work, so that the longest scans do not end the
    batch alone; with a client also as task priorities) or "input"; the table is in input order."""
    if transfer not in ("paths", "bytes"):
        raise ValueError("cagekit.batch.run: transfer must be 'paths' or 'bytes', not %r" % (transfer,))
    if order not in ("largest", "input"):
        raise ValueError("cagekit.batch.run: order must be 'largest' or 'input', not %r" % (order,))
    if method not in ("simplify", "quad", "anisotropic"):
        raise ValueError("cagekit.batch.run: method must be 'simplify', 'quad' or 'anisotropic', not %r" % (method,))
    entries = _expand(paths)
    names = scan_names(entries)
    scan_paths = [os.path.abspath(p) if transfer == "paths" else p for p, _ in entries]
    out_dir = os.path.abspath(os.fspath(out_dir))
    os.makedirs(out_dir, exist_ok=True)
    arguments = cli_arguments(method, options)
    if method == "simplify" and "--faces" not in arguments and "--vertices" not in arguments:
        raise ValueError("cagekit.batch.run: method 'simplify' needs options={'faces': N} or {'vertices': N}")
    given_threads = any(a == "--threads" for a in arguments)
    if client is None:
        jobs = int(jobs or os.cpu_count() or 1)
        if jobs < 1:
            raise ValueError("cagekit.batch.run: jobs must be >= 1")
        parallel = jobs > 1
        cli = find_cli(cli)  # here, once: a missing CLI is an error before anything runs
    else:
        parallel = _per_host_threads(client) > 1
    forwarded = list(arguments)
    if parallel and not given_threads:
        arguments = arguments + ["--threads", "1"]
    if thumbnails:
        arguments = arguments + ["--thumbnails"]

    start = time.monotonic()
    rows = [None] * len(entries)
    todo = []
    pipeline_arguments = [a for a in arguments if a != "--thumbnails"]
    for i, (path, name) in enumerate(zip(scan_paths, names)):
        earlier = _earlier(out_dir, path, name, pipeline_arguments) if resume or retry_failed else None
        if earlier is not None and retry_failed and earlier["status"] != "ok":
            earlier = None
        if earlier is not None:
            rows[i] = earlier
        else:
            todo.append(i)
    if order == "largest":
        work = {i: estimated_work(scan_paths[i]) for i in todo}
        todo.sort(key=lambda i: -work[i])  # stable: input order among equals

    def fill(i, outcome):
        row, files = outcome
        if files is not None:
            _write_files(out_dir, names[i], files)
        rows[i] = row
        return row

    if client is None:
        bar = _ConsoleBar(len(todo), progress)
        with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
            futures = {}
            for i in todo:
                data = None
                if transfer == "bytes":
                    with open(scan_paths[i], "rb") as f:
                        data = f.read()
                futures[pool.submit(run_scan, scan_paths[i], names[i], arguments, cli, timeout, memory_limit, data,
                                    out_dir if transfer == "paths" else None, retries)] = i
            for future in concurrent.futures.as_completed(futures):
                i = futures[future]
                try:
                    row = fill(i, future.result())
                except OSError as e:  # the scan's folder in out_dir cannot be written
                    row = rows[i] = _failed_row(scan_paths[i], names[i], "failed", str(e))
                bar.update(row)
    else:
        import distributed  # noqa: F401  (only with a client)
        token = uuid.uuid4().hex[:8]
        futures = []
        for rank, i in enumerate(todo):
            data = None
            if transfer == "bytes":
                with open(scan_paths[i], "rb") as f:
                    data = client.scatter(f.read(), hash=False)
            futures.append(client.submit(run_scan, scan_paths[i], names[i], arguments, cli, timeout, memory_limit, data,
                                         out_dir if transfer == "paths" else None, retries, pure=False,
                                         retries=retries, key="cagekit-scan-%s-%d" % (token, i),
                                         priority=len(todo) - rank))
        if progress and futures:
            distributed.progress(futures)
        for i, future in zip(todo, futures):  # in start order: the rows' order comes from i
            try:
                fill(i, future.result())
            except ValueError:  # usage: wrong arguments for every scan
                raise
            except OSError as e:  # the scan's folder in out_dir cannot be written
                rows[i] = _failed_row(scan_paths[i], names[i], "failed", str(e))
            except Exception as e:  # the task itself failed (its worker died, no CLI there, ...)
                rows[i] = _failed_row(scan_paths[i], names[i], "crash", "task failed: %s: %s" % (type(e).__name__, e))

    meta = dict(input=paths if isinstance(paths, (str, os.PathLike)) else None, method=method, options=forwarded,
                jobs=jobs if client is None else None, timeout=timeout, memory_limit_mb=memory_limit or 0,
                seconds=time.monotonic() - start)
    if isinstance(meta["input"], os.PathLike):
        meta["input"] = os.fspath(meta["input"])
    _write_tables(out_dir, rows, meta)
    try:
        import pandas
    except ImportError:
        return rows
    return pandas.DataFrame(rows, columns=list(COLUMNS) + ["attempts"])
