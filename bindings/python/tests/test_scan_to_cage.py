# SPDX-License-Identifier: GPL-3.0-or-later
"""The whole journey in one call: conditioning, method, fit, judged report."""
import unittest

import numpy as np
from support import HandleCheck, grid_cube

import cagekit


class ScanToCage(HandleCheck):
    def test_a_noisy_grid_cube_becomes_a_good_fitted_cage(self):
        positions, triangles = grid_cube(6, noise=0.002)
        with cagekit.Mesh.from_arrays(positions, triangles) as mesh:
            cage, limit, report = cagekit.scan_to_cage(mesh, faces=6)
            with cage, limit:
                self.assertEqual(report.used_method, cagekit.ScanMethod.SIMPLIFY)
                self.assertFalse(report.fallback)
                self.assertEqual(report.fallback_reason, "")
                self.assertEqual((report.cage_faces, report.cage_quads, report.creases), (6, 6, 12))
                self.assertEqual(report.conditioned_faces, len(triangles))
                self.assertLess(report.limit_to_scan_max_rel, 0.01)
                self.assertLess(report.scan_to_limit_max_rel, 0.01)
                self.assertEqual(report.self_intersections, 0)
                self.assertEqual(cage.info().faces, 6)
                self.assertEqual(limit.info().faces, 6 * 4 ** 3)
                self.assertIsInstance(report.two_sided_refit, bool)
                if report.two_sided_refit:
                    self.assertLess(max(report.scan_to_limit_max_rel, report.limit_to_scan_max_rel),
                                    0.95 * report.one_sided_fit_max_rel)
            cage, limit, off = cagekit.scan_to_cage(mesh, faces=6, two_sided_refit_factor=0)
            with cage, limit:
                self.assertFalse(off.two_sided_refit)
                self.assertEqual(off.one_sided_fit_max_rel, 0.0)

    def test_a_soup_is_welded_and_a_stray_piece_can_be_dropped(self):
        positions, triangles = grid_cube(4)
        soup = positions[triangles.reshape(-1)]                    # every corner its own vertex
        soup_faces = np.arange(len(soup), dtype=np.uint32).reshape(-1, 3)
        stray = np.array([[5, 5, 5], [5.01, 5, 5], [5, 5.01, 5]])  # a separate tiny triangle
        all_positions = np.vstack([soup, stray])
        all_faces = np.vstack([soup_faces, np.array([[len(soup), len(soup) + 1, len(soup) + 2]], dtype=np.uint32)])
        with cagekit.Mesh.from_arrays(all_positions, all_faces) as mesh:
            cage, limit, report = cagekit.scan_to_cage(mesh, faces=6, components="largest")
            with cage, limit:
                self.assertEqual(report.welded_vertices, len(soup) - len(positions))
                self.assertEqual((report.dropped_components, report.dropped_component_faces), (1, 1))
                self.assertEqual(report.components, 1)
                self.assertEqual(report.cage_faces, 6)

    def test_bounds_that_cannot_be_met_raise_quality_error(self):
        positions, triangles = grid_cube(6, noise=0.002)
        with cagekit.Mesh.from_arrays(positions, triangles) as mesh:
            with self.assertRaises(cagekit.QualityError) as caught:
                cagekit.scan_to_cage(mesh, faces=6, max_limit_to_scan_rel=1e-12, limit_to_scan_factor=1e-12,
                                     small_input_faces=0)
            self.assertIn("strays", str(caught.exception))
            with self.assertRaises(cagekit.InvalidArgumentError):
                cagekit.scan_to_cage(mesh, faces=0)
            with self.assertRaises(cagekit.InvalidArgumentError):
                cagekit.scan_to_cage(mesh, faces=6, two_sided_refit_factor=-1)


if __name__ == "__main__":
    unittest.main()
