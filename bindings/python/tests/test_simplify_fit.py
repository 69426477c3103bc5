# SPDX-License-Identifier: GPL-3.0-or-later
"""Simplification (hierarchy, levels, clusters, cage) and fitting (error per pass)."""
import unittest

import numpy as np
from support import CUBE, CUBE_QUADS, HandleCheck, grid_cube, shared_mesh, sphere

import cagekit


class Simplification(HandleCheck):
    def test_a_noisy_grid_cube_simplifies_to_its_six_sides(self):
        n = 6
        positions, triangles = grid_cube(n, noise=0.002)
        with cagekit.Mesh.from_arrays(positions, triangles) as mesh, cagekit.Hierarchy(mesh) as hierarchy:
            levels = hierarchy.level_count
            self.assertEqual(hierarchy.level, levels - 1)  # starts at the coarsest
            first = hierarchy.level_info(0)
            self.assertEqual((first.faces, first.vertices, first.error), (len(triangles), len(positions), 0.0))
            level = hierarchy.set_level(faces=6)
            info = hierarchy.current_info()
            self.assertEqual((info.level, info.faces, info.vertices, info.invalid_faces), (level, 6, 8, 0))
            # six faces, one loop each, made of the cube's corners
            faces = hierarchy.faces()
            self.assertEqual([len(loops) for loops in faces], [1] * 6)
            corner_ids = {i for i, p in enumerate(positions) if np.all((p < 1e-9) | (p > 1 - 1e-9))}
            self.assertEqual({int(v) for loops in faces for v in loops[0]}, corner_ids)
            # the cluster map: each side's 2 n^2 triangles in one cluster
            clusters = hierarchy.clusters()
            self.assertEqual(clusters.shape, (len(triangles),))
            self.assertEqual(sorted(np.bincount(clusters)), [2 * n * n] * 6)
            cage, report = hierarchy.build_cage()
            with cage:
                self.assertEqual((report.quads, report.triangles, report.pentagons, report.creases), (6, 0, 0, 12))
                info = cage.info()
                self.assertEqual((info.vertices, info.faces, info.quads, info.creases, info.genus), (8, 6, 6, 12, 0))
                self.assertLess(mesh.measure_error(cage).hausdorff_rel, 0.01)  # a Cage's control mesh
            with hierarchy.polygon_mesh() as level_mesh:
                self.assertEqual(level_mesh.counts()[:2], (8, 6))
                error = mesh.measure_error(level_mesh)
                self.assertLess(error.hausdorff_rel, 0.01)
            # the cube's borders are straight: refined contours add no vertex
            with hierarchy.refined_polygon_mesh(0.01) as refined:
                self.assertEqual(refined.counts()[:2], (8, 6))
            with self.assertRaises(cagekit.InvalidArgumentError):
                hierarchy.refined_polygon_mesh(0.0)
            # the vertex query and the input level
            self.assertEqual(hierarchy.find_level(vertices=8), level)
            hierarchy.level = 0
            self.assertEqual(hierarchy.current_info().faces, len(triangles))
            with self.assertRaises(cagekit.InvalidArgumentError):
                hierarchy.level = levels
            with self.assertRaises(ValueError):
                hierarchy.find_level(faces=6, vertices=8)

    def test_simplify_to_n_faces_in_one_call(self):
        positions, triangles = grid_cube(4)
        with cagekit.Mesh.from_arrays(positions, triangles) as mesh:
            # Creases where the scan is sharp (the default): the cube's 12 edges at 90 degrees.
            cage, report = cagekit.simplify(mesh, faces=6)
            with cage:
                self.assertEqual((cage.info().quads, cage.info().creases, report.creases), (6, 12, 12))
            cage, report = cagekit.simplify(mesh, faces=6, feature_angle_degrees=95.0)
            with cage:
                self.assertEqual((cage.info().quads, cage.info().creases, report.creases), (6, 0, 0))
            # The thesis's rule by the clusters' normals.
            cage, report = cagekit.simplify(mesh, faces=6, crease_rule="cluster-angle", crease_angle_degrees=95.0)
            with cage:
                self.assertEqual((cage.info().quads, cage.info().creases, report.creases), (6, 0, 0))
            with self.assertRaises(ValueError):
                cagekit.simplify(mesh, faces=6, crease_rule="sharp")

    def test_the_fandisk_simplifies_to_at_most_n_faces(self):
        path = shared_mesh("fandisk.obj")
        with cagekit.Mesh.read(path) as scan, cagekit.Hierarchy(scan) as hierarchy:
            hierarchy.set_level(faces=300)
            self.assertLessEqual(hierarchy.current_info().faces, 300)
            self.assertGreater(hierarchy.current_info().faces, 250)
            cage, report = hierarchy.build_cage(crease_rule="cluster-angle", input_crease_angle_degrees=30)
            with cage:
                info = cage.info()
                self.assertEqual(info.faces, report.quads + report.triangles + report.pentagons +
                                 report.other_polygons)
                self.assertGreater(report.quads, info.faces / 2)  # quad-dominant
                self.assertEqual(report.non_manifold_edges, 0)
                self.assertGreater(info.creases, 0)

    def test_refined_contours_bring_a_coarse_sphere_level_closer(self):
        positions, triangles = sphere(rings=24, segments=48)
        with cagekit.Mesh.from_arrays(positions, triangles) as scan, cagekit.Hierarchy(scan) as hierarchy:
            hierarchy.set_level(faces=8)
            with hierarchy.polygon_mesh() as plain, hierarchy.refined_polygon_mesh(0.01) as refined:
                self.assertEqual(plain.counts()[1], refined.counts()[1])  # same faces
                self.assertGreater(refined.counts()[0], plain.counts()[0])  # more vertices
                # measured 13.7% -> 9.0% of the diagonal
                self.assertLess(scan.measure_error(refined).hausdorff_rel,
                                0.8 * scan.measure_error(plain).hausdorff_rel)


class Fitting(HandleCheck):
    def test_fit_reduces_the_error_every_pass(self):
        positions, triangles = sphere()
        with cagekit.Mesh.from_arrays(positions, triangles) as scan, \
                cagekit.Cage.from_arrays(CUBE, CUBE_QUADS) as cube:
            fitted, report = cagekit.fit(cube, scan, max_passes=4, tolerance=0.0, threads=2)
            with fitted:
                self.assertIs(type(fitted), cagekit.Cage)
                self.assertEqual(report.pass_count, len(report.passes))
                self.assertGreaterEqual(report.pass_count, 2)
                l2 = [p.l2 for p in report.passes]
                for before, after in zip(l2, l2[1:]):
                    self.assertLess(after, before)
                self.assertEqual(report.initial, report.passes[0])
                self.assertEqual(report.final, report.passes[report.best_pass])  # the best state by two-sided RMS
                self.assertLess(report.final.rms_rel, 0.5 * report.initial.rms_rel)
                self.assertAlmostEqual(report.bbox_diagonal, 1.5 * np.sqrt(3), places=2)
                self.assertFalse(report.fairing_used)
                np.testing.assert_array_equal(cube.positions, CUBE)  # the input cage is unchanged
                self.assertGreater(np.abs(fitted.positions - CUBE).sum(), 0.1)
                np.testing.assert_array_equal(fitted.faces, CUBE_QUADS)
            again, report = cube.fit(scan, max_passes=2, projection="piecewise_linear", solver="cgls")
            with again:
                self.assertIs(type(again), cagekit.Cage)
                self.assertLess(report.final.l2, report.initial.l2)
            with self.assertRaises(cagekit.InvalidArgumentError) as caught:
                cagekit.fit(cube, scan, tangential_weight=2.0)
            self.assertIn("tangential_weight", str(caught.exception))
            with self.assertRaises(ValueError):
                cagekit.fit(cube, scan, projection="sideways")


if __name__ == "__main__":
    unittest.main()
