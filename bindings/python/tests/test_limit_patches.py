# SPDX-License-Identifier: GPL-3.0-or-later
"""LimitPatches: the limit surface as bicubic Bezier patches (cagekit_limit_patches_*)."""
import unittest

import numpy as np
from support import CUBE, CUBE_QUADS, CUBE_EDGES, HandleCheck, shared_mesh

import cagekit


def grid_locations(patches, n=17, at_most=600):
    """(patch indices, (s, t)) of an n x n grid (where the SDK measures its errors) on every patch,
    or on `at_most` of them chosen at random, always with the one of the largest error."""
    g = np.linspace(0.0, 1.0, n)
    st = np.stack(np.meshgrid(g, g, indexing="ij"), axis=-1).reshape(-1, 2)
    chosen = np.arange(len(patches))
    if len(chosen) > at_most:
        rng = np.random.default_rng(3)
        chosen = np.union1d(rng.choice(chosen, at_most, replace=False), [int(np.argmax(patches.errors))])
    return np.repeat(chosen, len(st)), np.tile(st, (len(chosen), 1))


class LimitPatchChecks(HandleCheck):
    def check_patches(self, cage, tolerance, max_depth=8):
        """Common checks; returns (patches, per-sample distances at random (s, t), diag)."""
        patches = cagekit.LimitPatches(cage, tolerance=tolerance, max_depth=max_depth)
        info = patches.info
        n = info.patch_count
        self.assertGreater(n, 0)
        self.assertEqual(n, info.exact_count + info.approximated_count)
        self.assertEqual(len(patches), n)
        pos = cage.positions
        diag = float(np.linalg.norm(pos.max(0) - pos.min(0)))
        self.assertAlmostEqual(info.bbox_diagonal, diag, delta=1e-12 * diag)
        self.assertAlmostEqual(info.tolerance, tolerance * diag, delta=1e-12 * diag)
        cp, dom, ptex, exact, errors = (patches.control_points, patches.domains, patches.ptex_faces, patches.exact,
                                        patches.errors)
        self.assertEqual(cp.shape, (n, 4, 4, 3))
        self.assertEqual(dom.shape, (n, 4))
        self.assertEqual(int(exact.sum()), info.exact_count)
        self.assertEqual(int(np.count_nonzero(errors[~exact] > info.tolerance)), info.over_tolerance_count)
        if info.approximated_count:
            self.assertEqual(info.max_error, errors[~exact].max())
        self.assertAlmostEqual(info.max_error_rel, info.max_error / diag, delta=1e-15)
        # the squares are dyadic and tile every ptex face of the surface exactly
        width, height = dom[:, 2] - dom[:, 0], dom[:, 3] - dom[:, 1]
        np.testing.assert_array_equal(width, height)
        np.testing.assert_array_equal(np.log2(width), np.round(np.log2(width)))
        self.assertLessEqual(-np.log2(width).min(), max_depth + 1)  # n-gon sub-faces may start at depth 1
        with cage.surface() as surface:
            ptex_count = surface.counts()[0]
            area = np.bincount(ptex, weights=width * height, minlength=ptex_count)
            np.testing.assert_allclose(area, 1.0, rtol=0, atol=1e-12)
            self.assertTrue(np.all(np.diff(ptex.astype(np.int64)) >= 0), "ordered by ptex face")
            # the cage face of each patch is the one whose ptex faces contain it
            sizes = cage.face_arrays()[0]
            for k in np.unique(ptex)[:60]:
                face = int(patches.cage_faces[np.searchsorted(ptex, k)])
                corners = [surface.ptex_face(face, c) for c in range(1 if sizes[face] == 4 else int(sizes[face]))]
                self.assertIn(int(k), corners)
            # exact patches ARE the limit surface; approximated ones are within their error where
            # the SDK measures it (a 17 x 17 grid), and within twice it between the samples
            idx, st = grid_locations(patches)
            faces, uv = patches.ptex_locations(idx, st)
            limit = surface.evaluate(faces, uv).position
            d_grid = np.linalg.norm(patches.evaluate(idx, st) - limit, axis=1)
            rng = np.random.default_rng(5)
            ridx = rng.integers(0, n, 4000)
            rst = rng.random((4000, 2))
            rfaces, ruv = patches.ptex_locations(ridx, rst)
            d_random = np.linalg.norm(patches.evaluate(ridx, rst) - surface.evaluate(rfaces, ruv).position, axis=1)
        ex = exact[idx]
        if ex.any():
            self.assertLess(d_grid[ex].max(), 1e-12 * diag)
        self.assertTrue(np.all(d_grid[~ex] <= errors[idx][~ex] * (1 + 1e-9) + 1e-13 * diag),
                        "approximated patches within their reported error on the grid")
        rex = exact[ridx]
        if rex.any():
            self.assertLess(d_random[rex].max(), 1e-12 * diag)
        self.assertTrue(np.all(d_random <= 2.0 * errors[ridx] + 1e-12 * diag))
        if info.over_tolerance_count == 0:
            self.assertLessEqual(info.max_error, tolerance * diag)
        return patches, d_random, diag


class LimitPatchesOfGeneratedCages(LimitPatchChecks):
    def test_a_creased_cube_cage(self):
        with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS) as smooth, \
                cagekit.Cage.from_arrays(CUBE, CUBE_QUADS, creases=CUBE_EDGES) as creased:
            for cage in (smooth, creased):
                patches, d, diag = self.check_patches(cage, 1e-4)
                with patches:
                    info = patches.info
                    # smooth: approximated patches at the eight valence-3 corners, exact ones elsewhere
                    self.assertGreater(info.exact_count, 0)
                    if cage is smooth:
                        self.assertGreater(info.approximated_count, 0)
                    self.assertEqual(info.over_tolerance_count, 0)
                    self.assertLessEqual(info.max_error_rel, 1e-4)
                    np.testing.assert_array_equal(patches.ptex_faces, patches.cage_faces)  # all quads
            # a fully creased cube is the cube itself: every patch is exact and flat
            with cagekit.LimitPatches(creased) as patches:
                self.assertEqual(patches.info.approximated_count, 0)
                cp = patches.control_points.reshape(-1, 3)
                on_a_side = np.any((np.abs(cp) < 1e-12) | (np.abs(cp - 1) < 1e-12), axis=1)
                self.assertTrue(on_a_side.all())

    def test_a_coarser_tolerance_needs_fewer_patches(self):
        with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS) as cage, \
                cagekit.LimitPatches(cage, tolerance=1e-2) as coarse, \
                cagekit.LimitPatches(cage, tolerance=1e-5) as fine, \
                cagekit.LimitPatches(cage, tolerance=1e-5, max_depth=1) as shallow:
            self.assertLess(coarse.info.patch_count, fine.info.patch_count)
            self.assertLessEqual(fine.info.max_error_rel, 1e-5)
            self.assertLessEqual(coarse.info.max_error_rel, 1e-2)
            # depth 1 cannot reach 1e-5 at the extraordinary corners: kept and counted
            self.assertGreater(shallow.info.over_tolerance_count, 0)
            self.assertGreater(shallow.info.max_error_rel, 1e-5)
            self.assertEqual(int(np.count_nonzero(shallow.errors > shallow.info.tolerance)),
                             shallow.info.over_tolerance_count)

    def test_threads_do_not_change_the_patches(self):
        with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS) as cage, \
                cagekit.LimitPatches(cage, threads=1) as one, cagekit.LimitPatches(cage, threads=2) as two:
            np.testing.assert_array_equal(one.records(), two.records())

    def test_records_ranges_and_evaluate(self):
        with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS) as cage, cagekit.limit_patches(cage, 1e-3) as patches:
            n = patches.info.patch_count
            all_records = patches.records()
            np.testing.assert_array_equal(patches.records(3, 5), all_records[3:8])
            self.assertEqual(len(patches.records(n, 0)), 0)
            with self.assertRaises(cagekit.InvalidArgumentError):
                patches.records(n - 2, 5)
            raw = all_records["control_points"][7].reshape(4, 4, 3)  # [j, i]
            s, t = 0.3, 0.8
            bs = np.array([(1 - s) ** 3, 3 * s * (1 - s) ** 2, 3 * s * s * (1 - s), s ** 3])
            bt = np.array([(1 - t) ** 3, 3 * t * (1 - t) ** 2, 3 * t * t * (1 - t), t ** 3])
            by_hand = sum(bs[i] * bt[j] * raw[j, i] for i in range(4) for j in range(4))
            np.testing.assert_allclose(patches.evaluate(7, [s, t])[0], by_hand, rtol=0, atol=1e-15)
            np.testing.assert_array_equal(patches.control_points[7].transpose(1, 0, 2), raw)

    def test_bad_options_raise_with_the_sdk_message(self):
        with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS) as cage:
            for tolerance in (0.0, -1e-4, float("nan"), float("inf")):
                with self.assertRaises(cagekit.InvalidArgumentError) as caught:
                    cagekit.LimitPatches(cage, tolerance=tolerance)
                self.assertIn("tolerance", str(caught.exception))
            with self.assertRaises(cagekit.InvalidArgumentError) as caught:
                cagekit.LimitPatches(cage, max_depth=13)
            self.assertIn("max_depth", str(caught.exception))
            with self.assertRaises(cagekit.InvalidArgumentError) as caught:
                cagekit.LimitPatches(cage, threads=5000)
            self.assertIn("threads", str(caught.exception))

    def test_progress_and_cancel(self):
        stages = []
        with cagekit.Context(progress=lambda stage, f: stages.append((stage, f))) as ctx:
            with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS, context=ctx) as cage:
                with cagekit.LimitPatches(cage) as patches:
                    self.assertGreater(patches.info.patch_count, 0)
                self.assertIn("limit patches", {s for s, _ in stages})
                ctx.progress = lambda stage, f: False
                with self.assertRaises(cagekit.CancelledError):
                    cagekit.LimitPatches(cage)


class LimitPatchesOfARealCage(LimitPatchChecks):
    def test_the_fitted_fandisk_cage(self):
        path = shared_mesh("fandisk.obj")
        with cagekit.Mesh.read(path) as scan:
            cage0, _ = cagekit.simplify(scan, faces=200)
            with cage0:
                cage, _ = cagekit.fit(cage0, scan, max_passes=3)
        with cage:
            patches, d, diag = self.check_patches(cage, 1e-4)
            with patches:
                info = patches.info
                self.assertEqual(info.over_tolerance_count, 0)
                self.assertLessEqual(info.max_error_rel, 1e-4)
                self.assertGreater(info.exact_count, 0)
                self.assertGreater(info.approximated_count, 0)
                self.assertLess(d.max(), 2e-4 * diag)


if __name__ == "__main__":
    unittest.main()
