# SPDX-License-Identifier: GPL-3.0-or-later
"""Multiresolution editing: bind, deform, incremental update, .ckb round trips, sector split,
two Python threads deforming at once."""
import os
import tempfile
import threading
import unittest

import numpy as np
from support import CUBE, CUBE_QUADS, HandleCheck, shared_mesh, sphere

import cagekit


class Binding(HandleCheck):
    @classmethod
    def setUpClass(cls):
        positions, triangles = sphere()
        cls.scan_positions = positions
        cls.scan = cagekit.Mesh.from_arrays(positions, triangles)
        with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS) as cube:
            cls.fitted, _ = cagekit.fit(cube, cls.scan)

    @classmethod
    def tearDownClass(cls):
        cls.fitted.close()
        cls.scan.close()

    def test_undeformed_reproduces_the_scan_and_a_moved_point_moves_it(self):
        for mode in ("local_frame", "normal"):
            with cagekit.bind(self.fitted, self.scan, mode=mode) as binding, cagekit.CpuDeformer(binding) as deformer:
                info = binding.info()
                self.assertEqual((info.vertex_count, info.control_count), (len(self.scan_positions), 8))
                control = binding.control_points()
                np.testing.assert_array_equal(control, self.fitted.positions)
                positions, normals = deformer.deform(control)
                error = np.linalg.norm(positions - self.scan_positions, axis=1).max() / info.bbox_diagonal
                # within 1e-5 of the diagonal (float32 tables); normal mode also loses its sideways residual
                self.assertLess(error, 1e-5 + (info.max_sideways_residual if mode == "normal" else 0.0), mode)
                # unit normals (the compact deformer tables are float32)
                np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-6)
                self.assertGreater(np.sum(normals * (positions - 0.5), axis=1).min(), 0)  # outward
                moved = control.copy()
                moved[6] += (0.0, 0.0, 0.2)
                again, _ = deformer.deform(moved)
                shift = np.linalg.norm(again - positions, axis=1)
                self.assertGreater(shift.max(), 0.02)
                self.assertGreater(again[:, 2].max(), positions[:, 2].max())

    def test_update_equals_a_full_deform(self):
        with cagekit.bind(self.fitted, self.scan, mode="local_frame", exact_normals=True) as binding, \
                cagekit.CpuDeformer(binding) as full, cagekit.CpuDeformer(binding, threads=1) as incremental:
            control = binding.control_points()
            incremental.deform(control, normal_mode="exact")
            control[1, 0] += 0.1
            control[6, 2] -= 0.05
            p_inc, n_inc = incremental.update(control, moved=[1, 6], normal_mode="exact")
            self.assertGreater(incremental.updated_count, 0)
            p_full, n_full = full.deform(control, normal_mode=cagekit.NormalMode.EXACT)
            self.assertLess(np.abs(p_inc - p_full).max(), 1e-12)
            self.assertLess(np.abs(n_inc - n_full).max(), 1e-12)
            view, _ = full.deform(control, normals=False, copy=False)
            self.assertFalse(view.flags.writeable)
            with self.assertRaises(cagekit.InvalidArgumentError):
                incremental.update(control, moved=[99], normal_mode="exact")
            with self.assertRaises(ValueError):
                full.deform(control[:7])
            control[0, 0] = np.nan
            with self.assertRaises(cagekit.InvalidArgumentError):
                full.deform(control)
        with cagekit.bind(self.fitted, self.scan) as binding, cagekit.CpuDeformer(binding) as deformer:
            with self.assertRaises(cagekit.InvalidOperationError):  # a binding without exact-normal data
                deformer.deform(binding.control_points(), normal_mode="exact")

    def test_float32_outputs_are_the_float64_ones_rounded(self):
        with cagekit.bind(self.fitted, self.scan) as binding, cagekit.CpuDeformer(binding) as d64, \
                cagekit.CpuDeformer(binding, threads=2) as d32:
            control = binding.control_points()
            control[3] += (0.05, -0.02, 0.01)
            p64, n64 = d64.deform(control)
            p32, n32 = d32.deform(control, dtype="float32")
            self.assertEqual((p32.dtype, n32.dtype), (np.float32, np.float32))
            np.testing.assert_array_equal(p32, p64.astype(np.float32))
            np.testing.assert_array_equal(n32, n64.astype(np.float32))
            control[5, 1] += 0.04
            p64, n64 = d64.update(control, moved=[5])
            p32, n32 = d32.update(control, moved=[5])  # float32, as the last deform
            self.assertEqual(d32.updated_count, d64.updated_count)
            np.testing.assert_array_equal(p32, p64.astype(np.float32))
            np.testing.assert_array_equal(n32, n64.astype(np.float32))
            with self.assertRaises(ValueError):
                d32.deform(control, dtype="int32")
            with self.assertRaises(cagekit.InvalidArgumentError):
                d32.update(control, moved=[8])

    def test_scan_renumbered_in_the_deformer_order_deforms_the_same(self):
        positions, triangles = sphere()
        with cagekit.bind(self.fitted, self.scan) as binding:
            order = binding.deformer_vertex_order()
            self.assertEqual(order.dtype, np.uint32)
            np.testing.assert_array_equal(np.sort(order), np.arange(len(positions), dtype=np.uint32))
            new_id = np.empty_like(order)
            new_id[order] = np.arange(len(order), dtype=np.uint32)
            control = binding.control_points()
            control[2] += (0.03, 0.0, -0.02)
            with cagekit.CpuDeformer(binding) as d:
                before, _ = d.deform(control)
        with cagekit.Mesh.from_arrays(np.asarray(positions)[order], new_id[np.asarray(triangles)]) as renumbered, \
                cagekit.bind(self.fitted, renumbered) as again, cagekit.CpuDeformer(again) as d:
            after, _ = d.deform(control)
            np.testing.assert_allclose(after, before[order], atol=1e-9)
            # Bound in that order, the deformer's order is (nearly) the identity.
            self.assertGreater(np.mean(np.diff(again.deformer_vertex_order().astype(np.int64)) == 1), 0.9)

    def test_saved_bindings_round_trip_with_identical_deformations(self):
        with cagekit.bind(self.fitted, self.scan) as binding, tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "sphere.ckb")
            binding.save(path)
            data = binding.to_bytes()
            self.assertEqual(os.path.getsize(path), len(data))
            control = binding.control_points()
            control[0] += 0.05
            with cagekit.CpuDeformer(binding) as d0:
                expected = d0.deform(control)
            for loaded in (cagekit.Binding.load(path), cagekit.Binding.from_bytes(data, threads=1)):
                with loaded, cagekit.CpuDeformer(loaded) as d1:
                    self.assertEqual(loaded.info(), binding.info())
                    got = d1.deform(control)
                    np.testing.assert_array_equal(got[0], expected[0])
                    np.testing.assert_array_equal(got[1], expected[1])
                    self.assertEqual(loaded.to_bytes(), data)
                    np.testing.assert_array_equal(loaded.vertex_sources(), np.arange(len(self.scan_positions)))
                    self.assertIsNone(loaded.face_arrays())
            with self.assertRaises(cagekit.ParseError):
                cagekit.Binding.from_bytes(data[:len(data) // 2])
            with self.assertRaises(cagekit.ParseError) as caught:
                cagekit.Binding.from_bytes(b"X" + data[1:64])
            self.assertIn("CAGEKITB", str(caught.exception))
            with self.assertRaises(cagekit.FileIOError):
                cagekit.Binding.load(os.path.join(tmp, "missing.ckb"))

    def test_sector_split_binds_one_copy_per_smooth_sector(self):
        with cagekit.Mesh.from_arrays(CUBE, CUBE_QUADS) as mesh, cagekit.Cage(mesh) as cube, \
                cagekit.bind(cube, mesh, sharp_angle_degrees=45.0) as binding:
            info = binding.info()
            self.assertTrue(info.has_sector_split)
            self.assertEqual((info.scan_vertex_count, info.vertex_count), (8, 24))
            sources = binding.vertex_sources()
            np.testing.assert_array_equal(sources[:8], np.arange(8))
            self.assertTrue(np.all(sources < 8))
            sizes, flat = binding.face_arrays()
            self.assertEqual((len(sizes), len(flat)), (6, 24))
            with cagekit.CpuDeformer(binding) as deformer:
                positions, _ = deformer.deform(binding.control_points())
                self.assertEqual(positions.shape, (24, 3))
            with self.assertRaises(cagekit.InvalidArgumentError):
                cagekit.bind(cube, mesh, sharp_angle_degrees=181.0)

    def test_two_threads_deform_at_once_as_serially(self):
        with cagekit.bind(self.fitted, self.scan) as binding:
            base = binding.control_points()
            rng = np.random.default_rng(7)
            frames = [[base + rng.normal(0, 0.05, base.shape) for _ in range(40)] for _ in range(2)]
            with cagekit.CpuDeformer(binding, threads=1) as d:
                serial = [[d.deform(c) for c in thread_frames] for thread_frames in frames]
            results = [None, None]
            barrier = threading.Barrier(2)

            def work(k):
                with cagekit.CpuDeformer(binding, threads=1) as deformer:  # one deformer per thread
                    barrier.wait()
                    results[k] = [deformer.deform(c) for c in frames[k]]

            threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
            for t in threads:
                t.start()
            for t in threads:
                t.join(120)
            for k in range(2):
                self.assertEqual(len(results[k]), len(frames[k]))
                for (p, n), (ps, ns) in zip(results[k], serial[k]):
                    np.testing.assert_array_equal(p, ps)
                    np.testing.assert_array_equal(n, ns)


class RealScan(HandleCheck):
    def test_fandisk_bound_to_its_fitted_cage(self):
        path = shared_mesh("fandisk.obj")
        with cagekit.Mesh.read(path) as scan:
            cage, _ = cagekit.simplify(scan, faces=200)
            with cage:
                fitted, report = cagekit.fit(cage, scan, max_passes=3, keep_crease_vertices=True)
            with fitted, cagekit.bind(fitted, scan, mode="local_frame") as binding, \
                    cagekit.CpuDeformer(binding) as deformer:
                self.assertLessEqual(report.final.l2, report.initial.l2)
                diagonal = binding.info().bbox_diagonal
                control = binding.control_points()
                positions, _ = deformer.deform(control)
                original = scan.positions
                self.assertLess(np.linalg.norm(positions - original, axis=1).max(), 1e-5 * diagonal)
                control[0] += 0.05 * diagonal
                moved, _ = deformer.update(control, moved=[0])
                shift = np.linalg.norm(moved - original, axis=1)
                self.assertGreater(shift.max(), 0.01 * diagonal)
                self.assertGreater(np.count_nonzero(shift < 1e-9 * diagonal), 0)  # local support


if __name__ == "__main__":
    unittest.main()
