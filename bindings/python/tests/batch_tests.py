# SPDX-License-Identifier: GPL-3.0-or-later
"""cagekit.batch (issue 28): the local pool, a 2-worker Dask LocalCluster (paths and bytes) and the
`cagekit batch` CLI give the same rows on a folder mixing good and bad scans; crashes and timeouts of
a stand-in worker stay in their scan and are retried. Run by ctest as python.batch (CAGEKIT_CLI,
CAGEKIT_TEST_FAKE_PIPELINE); not part of python.bindings' discovery (file name batch_tests.py)."""
import contextlib
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))  # bindings/python: the package under test
# The LocalCluster's worker processes import cagekit.batch too.
os.environ["PYTHONPATH"] = os.pathsep.join([os.path.dirname(HERE)] + [p for p in os.environ.get("PYTHONPATH", "")
                                                                       .split(os.pathsep) if p])

import cagekit.batch as batch  # noqa: E402

try:
    CLI = batch.find_cli()
except FileNotFoundError as e:
    CLI, NO_CLI = None, str(e)
try:
    import distributed
except ImportError as e:
    distributed, NO_DASK = None, "distributed is not importable (apt install python3-distributed): %s" % e


def sphere_off(path, rings=10, segments=20):
    pts = [(0.0, 0.0, 1.0)]
    for r in range(1, rings):
        t = math.pi * r / rings
        pts += [(math.sin(t) * math.cos(2 * math.pi * k / segments), math.sin(t) * math.sin(2 * math.pi * k / segments),
                 math.cos(t)) for k in range(segments)]
    pts.append((0.0, 0.0, -1.0))
    tris = [(0, 1 + k, 1 + (k + 1) % segments) for k in range(segments)]
    for r in range(1, rings - 1):
        for k in range(segments):
            a, b = 1 + (r - 1) * segments + k, 1 + (r - 1) * segments + (k + 1) % segments
            tris += [(a, a + segments, b + segments), (a, b + segments, b)]
    base = 1 + (rings - 2) * segments
    tris += [(base + k, len(pts) - 1, base + (k + 1) % segments) for k in range(segments)]
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(pts), len(tris)))
        f.writelines("%.9g %.9g %.9g\n" % p for p in pts)
        f.writelines("3 %d %d %d\n" % t for t in tris)


def rows_of(table):
    """[(scan, status, faces)] of a run()'s table (a list of dicts or a DataFrame)."""
    if hasattr(table, "to_dict"):
        table = table.to_dict("records")
    return [(r["scan"], r["status"], r["faces"]) for r in table]


@contextlib.contextmanager
def batch_worker(command):
    """CAGEKIT_BATCH_WORKER set to `command` (inherited by each child `cagekit batch`), restored after."""
    old = os.environ.get("CAGEKIT_BATCH_WORKER")
    os.environ["CAGEKIT_BATCH_WORKER"] = command
    try:
        yield
    finally:
        if old is None:
            del os.environ["CAGEKIT_BATCH_WORKER"]
        else:
            os.environ["CAGEKIT_BATCH_WORKER"] = old


@contextlib.contextmanager
def local_cluster(processes):
    """A client of a 2-worker LocalCluster (1 thread each): worker processes or worker threads."""
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=processes, dashboard_address=None,
                                  silence_logs=40) as cluster, distributed.Client(cluster) as client:
        yield client


def as_list(table):
    return table.to_dict("records") if hasattr(table, "to_dict") else table


@unittest.skipIf(CLI is None, "no cagekit CLI: %s" % (NO_CLI if CLI is None else ""))
class Batch(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp(prefix="cagekit-batch-test-")
        cls.scans = os.path.join(cls.work, "in")
        os.makedirs(cls.scans)
        sphere_off(os.path.join(cls.scans, "ball.off"), 10, 20)
        sphere_off(os.path.join(cls.scans, "fine.off"), 14, 28)
        with open(os.path.join(cls.scans, "points.ply"), "w") as f:  # a point cloud: no faces
            f.write("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                    "end_header\n0 0 0\n1 0 0\n0 1 0\n")
        with open(os.path.join(cls.scans, "corrupt.off"), "w") as f:
            f.write("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n")
        cls.expected_status = {"ball": "ok", "fine": "ok", "points": "failed", "corrupt": "failed"}
        cls.local = batch.run(cls.scans, os.path.join(cls.work, "local"), method="simplify", options={"faces": 60},
                              jobs=2, timeout=120, progress=False)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.work, ignore_errors=True)

    def test_local_pool(self):
        rows = as_list(self.local)
        self.assertEqual({r["scan"]: r["status"] for r in rows}, self.expected_status)
        for r in rows:
            if r["status"] == "ok":
                self.assertGreater(r["faces"], 0)
                self.assertGreater(r["two_sided_error"], 0)
                for f in ("cage.obj", "limit.obj", "report.json", "result.json"):
                    self.assertTrue(os.path.isfile(os.path.join(self.work, "local", r["scan"], f)), f)
            else:
                self.assertTrue(r["message"])
        with open(os.path.join(self.work, "local", "results.json")) as f:
            table = json.load(f)
        self.assertEqual(table["summary"]["ok"], 2)
        self.assertEqual([r["scan"] for r in table["rows"]], sorted(self.expected_status))
        with open(os.path.join(self.work, "local", "ball", "result.json")) as f:
            self.assertEqual(json.load(f)["file"], os.path.join(self.scans, "ball.off"))

    def test_same_rows_as_the_cli(self):
        out = os.path.join(self.work, "cli")
        p = subprocess.run([CLI, "batch", self.scans, out, "--method", "simplify", "--faces", "60", "--jobs", "2",
                            "--quiet"], capture_output=True, text=True)
        self.assertEqual(p.returncode, 2, p.stderr)
        with open(os.path.join(out, "results.json")) as f:
            cli_rows = [(r["scan"], r["status"], r["faces"]) for r in json.load(f)["rows"]]
        self.assertEqual(rows_of(self.local), cli_rows)

    def test_resume_runs_nothing(self):
        out = os.path.join(self.work, "local")
        before = {n: os.stat(os.path.join(out, n, "result.json")).st_mtime_ns for n in self.expected_status}
        again = as_list(batch.run(self.scans, out, method="simplify", options={"faces": 60}, jobs=2, resume=True,
                                  progress=False))
        self.assertTrue(all(r["resumed"] for r in again))
        self.assertEqual(rows_of(again), rows_of(self.local))
        self.assertEqual(before, {n: os.stat(os.path.join(out, n, "result.json")).st_mtime_ns
                                  for n in self.expected_status})

    def test_retry_failed_runs_the_failed_ones(self):
        out = os.path.join(self.work, "retry")
        shutil.copytree(os.path.join(self.work, "local"), out)
        before = {n: os.stat(os.path.join(out, n, "result.json")).st_mtime_ns for n in self.expected_status}
        again = as_list(batch.run(self.scans, out, method="simplify", options={"faces": 60}, jobs=2,
                                  retry_failed=True, progress=False))
        after = {n: os.stat(os.path.join(out, n, "result.json")).st_mtime_ns for n in self.expected_status}
        failed = {n for n, s in self.expected_status.items() if s != "ok"}
        self.assertEqual({r["scan"] for r in again if not r["resumed"]}, failed)
        self.assertEqual({n for n in self.expected_status if before[n] != after[n]}, failed)
        self.assertEqual(rows_of(again), rows_of(self.local))

    @unittest.skipIf(distributed is None, NO_DASK if distributed is None else "")
    def test_local_cluster_of_threads(self):
        # The one-machine set-up the docs recommend: worker threads (each only waits on its scan's child).
        with local_cluster(processes=False) as client:
            rows = batch.run(self.scans, os.path.join(self.work, "dask-threads"), method="simplify",
                             options={"faces": 60}, client=client, timeout=120, progress=False)
        self.assertEqual(rows_of(rows), rows_of(self.local))
        # Two scans at once on one machine: each child got --threads 1, as with jobs=2.
        with open(os.path.join(self.work, "dask-threads", "ball", "result.json")) as f:
            options = json.load(f)["options"]
        self.assertIn("--threads", options)
        self.assertEqual(options[options.index("--threads") + 1], "1")

    def test_worker_hosts(self):
        self.assertEqual(batch._host("tcp://10.0.0.5:40123"), "10.0.0.5")
        self.assertEqual(batch._host("tls://[::1]:40123"), "[::1]")
        self.assertEqual(batch._host("inproc://192.0.2.2/14463/4"), "192.0.2.2")

    @unittest.skipIf(distributed is None, NO_DASK if distributed is None else "")
    def test_local_cluster_same_rows(self):
        # Worker processes, as on a real cluster (each task's child CLI runs under its worker process).
        with local_cluster(processes=True) as client:
            by_path = batch.run(self.scans, os.path.join(self.work, "dask"), method="simplify",
                                options={"faces": 60}, client=client, timeout=120, progress=False)
            by_bytes = batch.run(self.scans, os.path.join(self.work, "dask-bytes"), method="simplify",
                                 options={"faces": 60}, client=client, timeout=120, transfer="bytes", progress=False)
        self.assertEqual(rows_of(by_path), rows_of(self.local))
        self.assertEqual(rows_of(by_bytes), rows_of(self.local))
        for out in ("dask", "dask-bytes"):
            for f in ("cage.obj", "limit.obj", "report.json", "result.json"):
                self.assertTrue(os.path.isfile(os.path.join(self.work, out, "fine", f)), (out, f))
            with open(os.path.join(self.work, out, "results.json")) as f:
                self.assertEqual(json.load(f)["summary"]["ok"], 2)

    def stand_in(self, folder):
        """(the stand-in worker's path, a new scan folder in the work folder); skips without the stand-in."""
        fake = os.environ.get("CAGEKIT_TEST_FAKE_PIPELINE")
        if not fake:
            self.skipTest("CAGEKIT_TEST_FAKE_PIPELINE (tests/batch/fake_pipeline.sh) is not set")
        scans = os.path.join(self.work, folder)
        os.makedirs(scans, exist_ok=True)
        return fake, scans

    def test_isolation_and_retries(self):
        fake, scans = self.stand_in("fake-in")
        for name in ("crash", "hang", "ok", "error"):
            with open(os.path.join(scans, name + ".off"), "w") as f:
                f.write("OFF\n0 0 0\n")
        with batch_worker("sh " + fake):
            rows = as_list(batch.run(scans, os.path.join(self.work, "fake"), method="quad", jobs=4, timeout=1,
                                     retries=1, progress=False))
        got = {r["scan"]: (r["status"], r["attempts"]) for r in rows}
        # crash and timeout are retried once; a clean failure is not.
        self.assertEqual(got, {"crash": ("crash", 2), "hang": ("timeout", 2), "ok": ("ok", 1), "error": ("failed", 1)})

    def test_order(self):
        # Largest first by estimated work (file size over the format's bytes per triangle); the table in input order.
        fake, scans = self.stand_in("order-in")
        sizes = {"a.off": 100, "b.off": 9000, "c.stl": 84 + 50 * 60, "d.drc": 300}
        for name, size in sizes.items():
            with open(os.path.join(scans, name), "wb") as f:
                f.write(b"\0" * size)
        self.assertAlmostEqual(batch.estimated_work(os.path.join(scans, "b.off")), 200.0)
        self.assertAlmostEqual(batch.estimated_work(os.path.join(scans, "c.stl")), (84 + 50 * 60) / 50.0)
        self.assertAlmostEqual(batch.estimated_work(os.path.join(scans, "d.drc")), 100.0)
        self.assertEqual(batch.estimated_work(os.path.join(scans, "missing.off")), 0.0)
        with batch_worker("sh " + fake):
            def started(out, **kw):
                rows = as_list(batch.run(scans, os.path.join(self.work, out), method="quad", progress=False, **kw))
                self.assertEqual([r["scan"] for r in rows], ["a", "b", "c", "d"])
                times = {r["scan"]: os.stat(os.path.join(self.work, out, r["scan"], "argv.txt")).st_mtime_ns
                         for r in rows}
                return sorted(times, key=times.get)
            self.assertEqual(started("order-largest", jobs=1), ["b", "d", "c", "a"])
            self.assertEqual(started("order-input", jobs=1, order="input"), ["a", "b", "c", "d"])
            if distributed is not None:
                with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                              dashboard_address=None, silence_logs=40) as cluster, \
                        distributed.Client(cluster) as client:
                    self.assertEqual(started("order-dask", client=client), ["b", "d", "c", "a"])
            with self.assertRaises(ValueError):
                batch.run(scans, os.path.join(self.work, "order-bad"), method="quad", order="smallest",
                          progress=False)

    def test_usage_errors_raise(self):
        with self.assertRaises(ValueError):
            batch.run(self.scans, os.path.join(self.work, "bad"), method="simplify", options={}, progress=False)
        with self.assertRaises(ValueError):
            batch.run(self.scans, os.path.join(self.work, "bad"), method="quadx", options={"faces": 9},
                      progress=False)
        # An option the CLI does not know: its usage error (exit 64) raises, it is no scan's failure.
        with self.assertRaisesRegex(ValueError, "--bogus"):
            batch.run(self.scans, os.path.join(self.work, "bad"), method="quad", options={"bogus": 1}, jobs=1,
                      progress=False)

    def test_options(self):
        self.assertEqual(batch.cli_arguments("quad", {"fit_tolerance": 1e-3, "--no-fallback": True, "faces": None,
                                                      "no_repair": False}),
                         ["--method", "quad", "--fit-tolerance", "0.001", "--no-fallback"])
        with self.assertRaises(ValueError):
            batch.cli_arguments("quad", {"jobs": 2})
        self.assertEqual(batch.scan_names(["a/x.off", "b/x.off", "b/x.ply", ("c/y.off", "named")]),
                         ["x", "x.off", "x.ply", "named"])


if __name__ == "__main__":
    unittest.main()
