# SPDX-License-Identifier: GPL-3.0-or-later
"""Contexts: progress callbacks (stages, cancelling), Python exceptions inside callbacks, log,
cancel from another thread, memory budget, deterministic handle release."""
import gc
import signal
import threading
import unittest

import numpy as np
from support import CUBE, CUBE_EDGES, CUBE_QUADS, HandleCheck, sphere

import cagekit


def creased_cube(context):
    return cagekit.Cage.from_arrays(CUBE, CUBE_QUADS, creases=CUBE_EDGES, context=context)


class Boom(Exception):
    pass


class Progress(HandleCheck):
    def test_progress_sees_the_stages_of_each_operation(self):
        seen = []
        with cagekit.Context(progress=lambda stage, fraction: seen.append((stage, fraction))) as ctx:
            with creased_cube(ctx) as cage, cage.subdivide(levels=4) as fine:
                self.assertEqual(fine.info().faces, 6 * 4 ** 4)
            stages = [s for s, _ in seen]
            self.assertIn("subdivide", stages)
            for stage in set(stages):
                fractions = [f for s, f in seen if s == stage]
                self.assertTrue(all(0.0 <= f <= 1.0 for f in fractions), stage)
                self.assertEqual(fractions, sorted(fractions), "non-decreasing within " + stage)
            seen.clear()
            positions, triangles = sphere()
            with cagekit.Mesh.from_arrays(positions, triangles, context=ctx) as scan, \
                    cagekit.Cage.from_arrays(CUBE, CUBE_QUADS, context=ctx) as cube:
                fitted, report = cagekit.fit(cube, scan, max_passes=2, threads=2)
                fitted.close()
            self.assertIn("fit", [s for s, _ in seen])

    def test_returning_false_cancels_and_leaves_no_handle(self):
        calls = []

        def cancel(stage, fraction):
            calls.append(stage)
            return False

        with cagekit.Context(progress=cancel) as ctx, creased_cube(ctx) as cage:
            before = cagekit.live_handles()
            with self.assertRaises(cagekit.CancelledError) as caught:
                cage.subdivide(levels=4)
            self.assertEqual(caught.exception.status, -10)
            self.assertGreaterEqual(len(calls), 1)
            self.assertEqual(cagekit.live_handles(), before)
            # None and True continue
            ctx.progress = lambda stage, fraction: None
            with cage.subdivide(levels=2):
                pass
            ctx.progress = lambda stage, fraction: True
            with cage.subdivide(levels=2):
                pass

    def test_an_exception_in_the_callback_propagates_after_the_call_and_the_sdk_stays_usable(self):
        raised = Boom("raised inside the progress callback")

        def fail(stage, fraction):
            raise raised

        with cagekit.Context(progress=fail) as ctx, creased_cube(ctx) as cage:
            before = cagekit.live_handles()
            with self.assertRaises(Boom) as caught:
                cage.subdivide(levels=4)
            self.assertIs(caught.exception, raised)
            self.assertEqual(cagekit.live_handles(), before)
            positions, triangles = sphere()
            with cagekit.Mesh.from_arrays(positions, triangles, context=ctx) as scan:
                before = cagekit.live_handles()
                with self.assertRaises(Boom):  # also from a fit's worker-threaded call
                    cagekit.fit(cage, scan, max_passes=2)
                with self.assertRaises(Boom):
                    cagekit.Hierarchy(scan)
                self.assertEqual(cagekit.live_handles(), before)
                ctx.progress = None
                with cage.subdivide(levels=4) as fine:
                    self.assertEqual(fine.info().quads, 6 * 4 ** 4)
                fitted, _ = cagekit.fit(cage, scan, max_passes=1)
                fitted.close()

    @unittest.skipUnless(signal.getsignal(signal.SIGINT) is signal.default_int_handler,
                         "SIGINT is not Python's KeyboardInterrupt handler in this host (Blender handles Ctrl-C "
                         "itself): _thread.interrupt_main() is ignored")
    def test_ctrl_c_during_a_long_call_cancels_it_and_raises_keyboard_interrupt(self):
        import _thread
        calls = []

        def progress(stage, fraction):
            calls.append(stage)
            if len(calls) == 2:
                _thread.interrupt_main()  # as Ctrl-C: delivered in the next Python bytecode

        with cagekit.Context(progress=progress) as ctx, creased_cube(ctx) as cage:
            before = cagekit.live_handles()
            with self.assertRaises(KeyboardInterrupt):
                cage.subdivide(levels=6)
            self.assertEqual(cagekit.live_handles(), before)
            self.assertLess(len(calls), 10)  # cancelled at once
            ctx.progress = None
            with cage.subdivide(levels=1) as fine:
                self.assertEqual(fine.info().faces, 24)

    def test_python_threads_run_while_a_call_is_blocked_in_c(self):
        # A read from a FIFO blocks inside the C call until this thread writes the file: that can
        # only happen if the call released the GIL (else: a deadlock, ended by faulthandler).
        import faulthandler
        import os
        import tempfile
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "pipe.obj")
            os.mkfifo(path)
            result = []

            def read():
                try:
                    with cagekit.Mesh.read(path) as mesh:
                        result.append(mesh.counts())
                except Exception as e:  # reported below
                    result.append(e)

            faulthandler.dump_traceback_later(120, exit=True)
            try:
                reader = threading.Thread(target=read)
                reader.start()
                with open(path, "w") as f:
                    f.write("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
                reader.join(60)
            finally:
                faulthandler.cancel_dump_traceback_later()
            self.assertEqual(result, [(3, 1, 3)])

    def test_calls_release_the_gil(self):
        # ctypes.CDLL (not PyDLL) functions drop the GIL for the duration of each foreign call.
        import ctypes
        from cagekit import _lib
        self.assertIsInstance(_lib.lib, ctypes.CDLL)
        self.assertNotIsInstance(_lib.lib, ctypes.PyDLL)
        self.assertEqual(_lib.lib.cagekit_cpu_deformer_deform._flags_ & ctypes._FUNCFLAG_PYTHONAPI, 0)

    def test_cancel_from_another_thread(self):
        started, cancelled = threading.Event(), threading.Event()

        def progress(stage, fraction):
            started.set()
            cancelled.wait(10)  # releases the GIL: the main thread cancels meanwhile

        positions, triangles = sphere(24, 48)
        with cagekit.Context(progress=progress) as ctx, \
                cagekit.Mesh.from_arrays(positions, triangles, context=ctx) as scan, \
                cagekit.Cage.from_arrays(CUBE, CUBE_QUADS, context=ctx) as cube:
            result = []

            def work():
                try:
                    cagekit.fit(cube, scan, max_passes=50, tolerance=0.0)
                    result.append("finished")
                except cagekit.CancelledError as e:
                    result.append(e)

            worker = threading.Thread(target=work)
            worker.start()
            self.assertTrue(started.wait(10))
            ctx.cancel()
            cancelled.set()
            worker.join(60)
            self.assertIsInstance(result[0], cagekit.CancelledError)
            with self.assertRaises(cagekit.CancelledError):  # still cancelled until reset
                cube.subdivide(levels=1)
            ctx.reset_cancel()
            ctx.progress = None
            with cube.subdivide(levels=1) as fine:
                self.assertEqual(fine.info().faces, 24)


class Log(HandleCheck):
    def test_log_receives_warnings_and_its_exceptions_propagate(self):
        messages = []
        ctx = cagekit.Context(log=lambda level, message: messages.append((level, message)),
                              log_level=cagekit.LogLevel.DEBUG)
        with creased_cube(ctx) as cage:
            cage.to_bytes("ply")  # drops the tags: a warning
            self.assertTrue(any(level == cagekit.LogLevel.WARNING for level, _ in messages), messages)
        ctx.close()

        def fail(level, message):
            raise Boom(message)

        ctx = cagekit.Context(log=fail)
        with creased_cube(ctx) as cage:
            before = cagekit.live_handles()
            with self.assertRaises(Boom):
                cage.to_bytes("off")
            self.assertEqual(cagekit.live_handles(), before)
            self.assertGreater(len(cage.to_bytes("obj")), 0)  # no warning: no exception
        ctx.close()


class Resources(HandleCheck):
    def test_memory_budget_raises_out_of_memory(self):
        with cagekit.Context(memory_budget_bytes=1 << 20) as ctx, creased_cube(ctx) as cage:
            with cage.subdivide(levels=2):
                pass
            with self.assertRaises(cagekit.OutOfMemoryError) as caught:
                cage.subdivide(levels=7)
            self.assertIsInstance(caught.exception, MemoryError)
            self.assertIn("memory budget", str(caught.exception))

    def test_handles_are_released_deterministically(self):
        start = cagekit.live_handles()
        ctx = cagekit.Context()
        mesh = cagekit.Mesh.from_arrays(CUBE, CUBE_QUADS, context=ctx)
        with cagekit.Cage(mesh) as cage:
            self.assertEqual(cagekit.live_handles(), start + 3)
        self.assertTrue(cage.closed)
        with self.assertRaises(ValueError):
            cage.info()
        ctx.close()  # the mesh keeps the C context alive
        self.assertEqual(mesh.info().quads, 6)
        with self.assertRaises(ValueError):
            cagekit.Mesh.from_arrays(CUBE, CUBE_QUADS, context=ctx)
        del mesh  # __del__ releases
        self.assertEqual(cagekit.live_handles(), start)
        gc.collect()
        self.assertEqual(cagekit.live_handles(), start)

    def test_many_objects_do_not_leak(self):
        start = cagekit.live_handles()
        for _ in range(200):
            mesh = cagekit.Mesh.from_arrays(CUBE, CUBE_QUADS)
            cage = cagekit.Cage(mesh)
            cage.mesh().positions
        del mesh, cage
        self.assertEqual(cagekit.live_handles(), start)
        np.testing.assert_array_equal(cagekit.Mesh.from_arrays(CUBE, CUBE_QUADS).positions, CUBE)


if __name__ == "__main__":
    unittest.main()
