# SPDX-License-Identifier: GPL-3.0-or-later
"""cagekit.remesh_anisotropic / remesh_quad (cagekit_mesh_remesh_anisotropic / _quad): the
anisotropic method on an open cylinder, the quad method on a cube, the reports, and bad input /
options as exceptions."""
import math

import numpy as np

import cagekit
from support import HandleCheck, grid_cube


def open_cylinder(rings=40, segments=64, radius=1.0, height=3.0):
    """A triangulated open cylinder around the z axis (boundary circles at z = 0 and z = height)."""
    pts = [(radius * math.cos(2 * math.pi * k / segments), radius * math.sin(2 * math.pi * k / segments),
            height * r / rings) for r in range(rings + 1) for k in range(segments)]
    tris = []
    for r in range(rings):
        for k in range(segments):
            a, b = r * segments + k, r * segments + (k + 1) % segments
            c, d = a + segments, b + segments
            tris += [(a, b, d), (a, d, c)]
    return np.array(pts, dtype=np.float64), np.array(tris, dtype=np.uint32)


class Remesh(HandleCheck):
    def test_a_cylinder_becomes_quads_along_its_curvature_lines(self):
        positions, triangles = open_cylinder()
        with cagekit.Mesh.from_arrays(positions, triangles) as mesh:
            cage, report = cagekit.remesh_anisotropic(mesh, tolerance=0.002, feature_angle_degrees=-1)
            with cage:
                info = cage.info()
                self.assertEqual((info.faces, info.vertices), (report.faces, report.vertices))
                self.assertGreater(report.faces, 50)
                self.assertGreater(report.quads, 0.8 * report.faces)  # curvature lines: a grid of quads
                self.assertLessEqual(report.max_face_valence, 5)
                self.assertLess(report.mean_alignment_deg, 5.0)
                self.assertEqual(report.holes, 0)
                self.assertGreater(report.min_scaled_jacobian, 0.0)  # no concave corner
                self.assertLess(mesh.measure_error(cage).hausdorff_rel, 0.02)

    def test_quad_method_gives_a_closed_quad_dominant_cage(self):
        positions, triangles = grid_cube(6)
        with cagekit.Mesh.from_arrays(positions, triangles) as mesh:
            cage, report = cagekit.remesh_quad(mesh, regions=6, edge_length=0.1, weights=(100, 100, 100))
            with cage:
                info = cage.info()
                self.assertEqual((info.faces, info.vertices), (report.faces, report.vertices))
                self.assertTrue(info.manifold)
                self.assertEqual((info.genus, info.boundary_edges), (0, 0))
                self.assertEqual(report.regions, 6)  # the six sides
                self.assertEqual((report.requested_regions, report.split_regions, report.layout_retries,
                                  report.mended_faces, report.reseeded_regions), (6, 0, 0, 0, 0))
                self.assertGreater(report.quads, 0.9 * report.faces)
                self.assertEqual(report.creases, info.creases)
                self.assertGreater(report.creases, 0)  # the twelve 90° edges are sharp region boundaries
                self.assertLess(mesh.measure_error(cage).hausdorff_rel, 0.02)
            with self.assertRaises(cagekit.InvalidArgumentError):
                cagekit.remesh_quad(mesh, edge_length=0.0)
            with self.assertRaises(cagekit.InvalidArgumentError):
                cagekit.remesh_quad(mesh, weights=(1, -1, 1))
            with self.assertRaises(ValueError):
                cagekit.remesh_quad(mesh, weights=(1, 1))
            # Host control of the segmentation: two adjacent triangles pinned, one seed.
            cage, report = cagekit.remesh_quad(mesh, regions=7, edge_length=0.1, weights=(100, 100, 100),
                                          pinned_regions=[[0, 1]], seed_faces=[100])
            with cage:
                self.assertEqual(report.regions, 7)
                self.assertTrue(cage.info().manifold)
            with self.assertRaises(cagekit.InvalidArgumentError):  # a seed inside the pinned set
                cagekit.remesh_quad(mesh, regions=7, edge_length=0.1, pinned_regions=[[0, 1]], seed_faces=[1])
            with self.assertRaises(cagekit.InvalidArgumentError):  # out of range
                cagekit.remesh_quad(mesh, regions=7, edge_length=0.1, seed_faces=[10 ** 6])

    def test_bad_options_and_input_are_exceptions(self):
        positions, triangles = grid_cube(4)
        with cagekit.Mesh.from_arrays(positions, triangles) as mesh:
            with self.assertRaises(cagekit.InvalidArgumentError) as caught:
                cagekit.remesh_anisotropic(mesh, tolerance=0.0)
            self.assertIn("cagekit_anisotropic_options.tolerance must be finite and in (0, 1], not 0",
                          str(caught.exception))
            with self.assertRaises(cagekit.InvalidArgumentError):
                cagekit.remesh_anisotropic(mesh, max_face_valence=2)
            with self.assertRaises(TypeError):  # each remesher takes only its own options
                cagekit.remesh_quad(mesh, tolerance=0.01)
        bad = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, float("nan")]], dtype=np.float64)
        with cagekit.Mesh.from_arrays(bad, np.array([[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]], dtype=np.uint32)) as m:
            with self.assertRaises(cagekit.InvalidMeshError):
                cagekit.remesh_anisotropic(m)
            with self.assertRaises(cagekit.InvalidMeshError):
                cagekit.remesh_quad(m)


class SharpEdges(HandleCheck):
    """The host's sharp edges (a ring halfway up a smooth cylinder, sharp by no angle) are kept by
    every method: the creases of each cage lie on the ring."""

    def test_every_method_keeps_the_ring(self):
        rings, segments = 16, 32
        positions, triangles = open_cylinder(rings=rings, segments=segments, height=4.0)
        row = rings // 2
        ring = [(row * segments + k, row * segments + (k + 1) % segments) for k in range(segments)]
        mid = 4.0 * row / rings

        def crease_heights(cage):
            points = cage.positions
            return {round(float(points[v][2]), 6) for pair in cage.creases[0] for v in pair}

        with cagekit.Mesh.from_arrays(positions, triangles) as mesh:
            cage, _ = cagekit.simplify(mesh, faces=12, sharp_edges=ring, tag_boundary_edges=False)
            with cage:
                self.assertEqual(crease_heights(cage), {mid})
            cage, report = cagekit.remesh_quad(mesh, regions=6, edge_length=0.08, crease_angle_degrees=-1,
                                               sharp_edges=ring)
            with cage:
                self.assertGreater(report.creases, 0)
                self.assertEqual(crease_heights(cage), {mid})
            cage, report = cagekit.remesh_anisotropic(mesh, tolerance=0.004, feature_angle_degrees=-1,
                                                      sharp_edges=ring)
            with cage:
                self.assertGreater(report.creases, 0)
                self.assertEqual(crease_heights(cage), {mid})
            cage, limit, report = cagekit.scan_to_cage(mesh, faces=12, sharp_edges=ring)
            with cage, limit:
                self.assertEqual((report.sharp_edges, report.sharp_edges_dropped), (segments, 0))
            with self.assertRaises(cagekit.InvalidArgumentError):  # not an edge of the mesh
                cagekit.remesh_quad(mesh, sharp_edges=[(0, 2 * segments + 5)])
