# SPDX-License-Identifier: GPL-3.0-or-later
"""Cages: tags, formats that keep them, subdivision, limit points and surface evaluation."""
import unittest
from unittest import mock

import numpy as np
from support import CUBE, CUBE_EDGES, CUBE_QUADS, HandleCheck

import cagekit


class CageTags(HandleCheck):
    def test_tags_round_trip_and_bad_tags_fail(self):
        with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS, creases=CUBE_EDGES, corners=[0], corner_sharpness=2.5,
                                      holes=[5]) as cage:
            pairs, sharpness = cage.creases
            self.assertEqual(pairs.shape, (12, 2))
            self.assertEqual({tuple(sorted(p)) for p in pairs}, {tuple(sorted(e)) for e in CUBE_EDGES})
            np.testing.assert_array_equal(sharpness, np.full(12, cagekit.SHARP, dtype=np.float32))
            verts, corner_sharpness = cage.corners
            self.assertEqual((list(verts), list(corner_sharpness)), ([0], [2.5]))
            self.assertEqual(list(cage.holes), [5])
            info = cage.info()
            self.assertEqual((info.creases, info.corners, info.holes, info.quads), (12, 1, 1, 6))
            cage.boundary_rule = cagekit.BoundaryRule.EDGES_AND_CORNERS
            self.assertEqual(cage.boundary_rule, cagekit.BoundaryRule.EDGES_AND_CORNERS)
            with self.assertRaises(cagekit.InvalidArgumentError) as caught:
                cage.set_creases([[0, 7]])  # a diagonal, not an edge
            self.assertIn("7", str(caught.exception))
            self.assertEqual(cage.info().creases, 12)  # unchanged
            with self.assertRaises(cagekit.InvalidArgumentError):
                cage.set_creases([[0, 1]], [-1.0])
            cage.set_creases(CUBE_EDGES[:3], [1.0, 2.0, 3.0])
            np.testing.assert_array_equal(np.sort(cage.creases[1]), np.float32([1, 2, 3]))

    def test_obj_and_draco_keep_the_tags_ply_and_off_drop_them(self):
        with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS, creases=CUBE_EDGES) as cage:
            for fmt, creases in (("obj", 12), ("drc", 12), ("ply", 0), ("off", 0)):
                with cagekit.Cage.from_bytes(cage.to_bytes(fmt)) as back:
                    info = back.info()
                    self.assertEqual((info.quads, info.vertices, info.creases), (6, 8, creases), fmt)
                    self.assertLess(np.abs(back.positions - CUBE).max(), 1e-3)

    def test_cage_positions_and_faces(self):
        with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS) as cage:
            np.testing.assert_array_equal(cage.positions, CUBE)
            np.testing.assert_array_equal(cage.faces, CUBE_QUADS)
            with cage.mesh() as mesh:
                self.assertEqual(mesh.counts(), (8, 6, 24))

    def test_the_control_mesh_is_read_once_and_handed_out_as_copies(self):
        with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS) as cage:
            first = cage.positions
            first[0] = 7.0  # the caller's copy
            with mock.patch.object(cagekit.Cage, "mesh", side_effect=AssertionError("C read again")):
                np.testing.assert_array_equal(cage.positions, CUBE)
                self.assertIsNot(cage.positions, cage.positions)
                sizes, flat = cage.face_arrays()
                flat[:] = 0
                np.testing.assert_array_equal(cage.face_arrays()[1], CUBE_QUADS.reshape(-1))
                np.testing.assert_array_equal(cage.faces, CUBE_QUADS)
                cage.set_creases(CUBE_EDGES)  # tags only: the cached control mesh stays right
                np.testing.assert_array_equal(cage.positions, CUBE)
        with self.assertRaises(ValueError):  # closed: no stale answer from the cache
            cage.positions


class Subdivision(HandleCheck):
    def test_subdivision_counts_and_tags(self):
        with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS, creases=CUBE_EDGES) as cage:
            for levels in (1, 2, 3):
                with cage.subdivide(levels) as fine:
                    info = fine.info()
                    self.assertEqual(info.quads, 6 * 4 ** levels)
                    self.assertEqual(info.creases, 12 * 2 ** levels)  # both halves stay sharp
            with cage.subdivide(2, limit_positions=True) as fine:
                # an all-sharp cube's limit surface is the cube itself
                positions = fine.positions
                self.assertLess(np.abs(np.minimum(positions, 1 - positions)).min(), 1e-12)
            with self.assertRaises(cagekit.InvalidArgumentError):
                cage.subdivide(cagekit.MAX_SUBDIVISION_LEVELS + 1)

    def test_limit_points_of_a_smooth_cube_lie_inside_it(self):
        with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS) as cage:
            points, normals = cage.limit_points()
            self.assertEqual(points.shape, (8, 3))
            np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-12)
            centred = points - 0.5  # inside the cube, all corners alike
            self.assertTrue(np.all(np.abs(centred) < 0.5))
            self.assertLess(np.abs(np.abs(centred) - np.abs(centred[0])).max(), 1e-12)
            # the same point as the surface evaluated at the corner of a face around vertex 0
            with cage.surface() as surface:
                corners = surface.evaluate(0, [[0, 0], [1, 0], [1, 1], [0, 1]]).position
                self.assertLess(np.linalg.norm(corners - points[0], axis=1).min(), 1e-12)
            # outward normals
            self.assertTrue(np.all(np.sum(normals * centred, axis=1) > 0))


class Evaluation(HandleCheck):
    def test_basis_is_a_partition_of_unity_and_matches_evaluate(self):
        with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS) as cage, cage.surface() as surface:
            ptex, controls = surface.counts()
            self.assertEqual((ptex, controls), (6, 8))
            self.assertEqual(surface.ptex_face(3), 3)
            uv = np.array([[0.5, 0.5], [0.1, 0.9], [0.0, 0.0]])
            points = surface.evaluate([2, 2, 2], uv)
            self.assertEqual(points.position.shape, (3, 3))
            for k in range(3):
                basis = surface.evaluate_basis(2, *uv[k])
                self.assertAlmostEqual(basis.w.sum(), 1.0, places=12)
                self.assertAlmostEqual(basis.wu.sum(), 0.0, places=12)
                np.testing.assert_allclose(basis.w @ CUBE[basis.indices], points.position[k], atol=1e-12)
                np.testing.assert_allclose(basis.wu @ CUBE[basis.indices], points.du[k], atol=1e-12)
            moved = CUBE * 2.0
            np.testing.assert_allclose(surface.evaluate(2, uv, control_positions=moved).position,
                                       2.0 * points.position, atol=1e-12)
            with self.assertRaises(cagekit.InvalidArgumentError):
                surface.evaluate([0], [[1.5, 0.5]])


if __name__ == "__main__":
    unittest.main()
