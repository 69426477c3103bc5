# SPDX-License-Identifier: GPL-3.0-or-later
"""Meshes: numpy round trips, every file format in memory and on disk, errors with messages."""
import os
import tempfile
import unittest

import numpy as np
from support import CUBE, CUBE_QUADS, HandleCheck, grid_cube, sphere

import cagekit


class MeshRoundTrips(HandleCheck):
    def test_buffers_round_trip_float64_and_float32(self):
        positions, triangles = sphere()
        with cagekit.Mesh.from_arrays(positions, triangles) as mesh:
            self.assertEqual(mesh.counts(), (len(positions), len(triangles), 3 * len(triangles)))
            np.testing.assert_array_equal(mesh.positions, positions)
            faces = mesh.faces
            self.assertIsInstance(faces, list)  # one type for every mesh
            self.assertEqual({(type(f), f.dtype, f.shape) for f in faces}, {(np.ndarray, np.dtype(np.uint32), (3,))})
            np.testing.assert_array_equal(np.array(faces), triangles)
            as32 = mesh.get_positions(np.float32)
            self.assertEqual(as32.dtype, np.float32)
            np.testing.assert_array_equal(as32, positions.astype(np.float32))
        with cagekit.Mesh.from_arrays(positions.astype(np.float32), triangles.astype(np.int64)) as mesh:
            np.testing.assert_array_equal(mesh.positions, positions.astype(np.float32).astype(np.float64))

    def test_polygon_forms(self):
        # a cube with one side split into two triangles: quads and triangles mixed
        faces = [list(f) for f in CUBE_QUADS[1:]] + [[0, 2, 3], [0, 3, 1]]
        sizes = np.array([len(f) for f in faces])
        flat = np.concatenate([np.array(f) for f in faces])
        for form in (dict(faces=faces), dict(faces=(sizes, flat)), dict(faces=flat, face_sizes=sizes)):
            with cagekit.Mesh.from_arrays(CUBE, **form) as mesh:
                got_sizes, got_flat = mesh.face_arrays()
                np.testing.assert_array_equal(got_sizes, sizes)
                np.testing.assert_array_equal(got_flat, flat)
                self.assertIsInstance(mesh.faces, list)
                self.assertEqual({f.dtype for f in mesh.faces}, {np.dtype(np.uint32)})
                self.assertEqual([list(f) for f in mesh.faces], faces)
                info = mesh.info()
                self.assertEqual((info.quads, info.triangles, info.genus, info.manifold), (5, 2, 0, 1))
            with cagekit.Cage.from_arrays(CUBE, **form) as cage:
                self.assertEqual([list(f) for f in cage.faces], faces)  # the same type as Mesh.faces
        with cagekit.Mesh.from_arrays(CUBE) as mesh:
            self.assertEqual(mesh.faces, [])  # no faces: still a list
        with self.assertRaises(ValueError):
            cagekit.Mesh.from_arrays(CUBE[:, :2], CUBE_QUADS)
        with self.assertRaises(ValueError):
            cagekit.Mesh.from_arrays(CUBE, [[0, -1, 2]])

    def test_every_format_round_trips_in_memory(self):
        positions, triangles = grid_cube(3, noise=0.01)
        with cagekit.Mesh.from_arrays(positions, triangles) as mesh:
            for fmt in ("obj", "ply", "off", "drc", cagekit.FileFormat.PLY):
                data, report = mesh.to_bytes(fmt, report=True)
                self.assertIsInstance(data, bytes)
                self.assertEqual(len(data), report.bytes)
                with cagekit.Mesh.from_bytes(data) as back:  # format sniffed
                    np.testing.assert_array_equal(back.faces, triangles, str(fmt))
                    # binary PLY is exact, OBJ and OFF text keep 9 significant digits, Draco quantizes
                    tolerance = {"drc": 2e-4, "obj": 1e-8, "off": 1e-8}.get(fmt, 0.0)
                    self.assertLessEqual(np.abs(back.positions - positions).max(), tolerance, fmt)
                    if fmt == "drc":
                        self.assertLess(report.max_position_error, 2e-4)
            ascii_ply = mesh.to_bytes("ply", ply_binary=False)
            self.assertTrue(ascii_ply.startswith(b"ply\nformat ascii"))
            with cagekit.Mesh.from_bytes(bytearray(ascii_ply), "ply") as back:
                np.testing.assert_array_equal(back.faces, triangles)
            with self.assertRaises(ValueError):
                mesh.to_bytes("auto")

    def test_every_format_round_trips_through_files(self):
        positions, triangles = sphere()
        with cagekit.Mesh.from_arrays(positions, triangles) as mesh, tempfile.TemporaryDirectory() as tmp:
            for ext in ("obj", "ply", "off", "drc"):
                path = os.path.join(tmp, "sphere." + ext)
                report = mesh.write(path)
                self.assertEqual(os.path.getsize(path), report.bytes)
                with cagekit.Mesh.read(path) as back:
                    self.assertEqual(back.counts(), mesh.counts())

    def test_stl_is_read_welded_and_not_written(self):
        # A binary STL (header starting with "solid", as many are) of the sphere's triangles:
        # the corners are welded back into the sphere's vertices.
        import struct
        positions, triangles = sphere()
        positions = positions.astype(np.float32).astype(np.float64)
        data = b"solid sphere".ljust(80, b" ") + struct.pack("<I", len(triangles))
        for t in triangles:
            data += struct.pack("<3f", 0, 0, 1) + positions[list(t)].astype("<f4").tobytes() + b"\0\0"
        with cagekit.Mesh.from_bytes(data) as back:  # sniffed by the binary size rule
            self.assertEqual(back.counts(), (len(positions), len(triangles), 3 * len(triangles)))
            np.testing.assert_array_equal(back.positions[np.array(back.faces)], positions[triangles])
        with cagekit.Mesh.from_arrays(positions, triangles) as mesh, tempfile.TemporaryDirectory() as tmp:
            with self.assertRaises(cagekit.UnsupportedFormatError) as caught:
                mesh.to_bytes("stl")
            self.assertIn("STL: writing is not supported", str(caught.exception))
            with self.assertRaises(cagekit.UnsupportedFormatError):
                mesh.write(os.path.join(tmp, "x.stl"))
            self.assertEqual(os.listdir(tmp), [])


class MeshErrors(HandleCheck):
    def test_corrupt_obj_bytes_are_a_parse_error_with_the_line(self):
        with self.assertRaises(cagekit.ParseError) as caught:
            cagekit.Mesh.from_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n", "obj")
        self.assertIn(":4", str(caught.exception))
        self.assertIn("vertex 7", caught.exception.message)
        self.assertEqual(caught.exception.status, -6)
        self.assertIsInstance(caught.exception, cagekit.CageKitError)
        with self.assertRaises(cagekit.ParseError):
            cagekit.Mesh.from_bytes(b"\x01\x02garbage", "drc")

    def test_a_missing_file_is_an_os_error(self):
        with self.assertRaises(cagekit.FileIOError) as caught:
            cagekit.Mesh.read("/nonexistent/dir/x.obj")
        self.assertIsInstance(caught.exception, OSError)
        self.assertIn("/nonexistent/dir/x.obj", str(caught.exception))

    def test_nan_positions_make_an_invalid_mesh(self):
        positions, triangles = sphere()
        positions[5, 1] = np.nan
        with cagekit.Mesh.from_arrays(positions, triangles) as mesh:
            with self.assertRaises(cagekit.InvalidMeshError) as caught:
                mesh.validate()
            self.assertIn("vertex 5", str(caught.exception))
            self.assertEqual(caught.exception.report.issues, {cagekit.MeshIssue.NON_FINITE_POSITION: 1})
            with self.assertRaises(cagekit.InvalidMeshError):
                cagekit.Cage(mesh)
            with self.assertRaises(cagekit.InvalidArgumentError) as caught:  # fit samples must be finite
                with cagekit.Cage(cagekit.Mesh.from_arrays(CUBE, CUBE_QUADS)) as cube:
                    cagekit.fit(cube, mesh)
            self.assertIsInstance(caught.exception, ValueError)
            repaired, report = mesh.repair()
            with repaired:
                self.assertTrue(repaired.validate().valid)
                self.assertEqual(report.removed_non_finite_vertices, 1)
                self.assertEqual(repaired.vertex_count, len(positions) - 1)

    def test_out_of_range_faces_are_named(self):
        with cagekit.Mesh.from_arrays(CUBE, [[0, 1, 2], [0, 9000, 2]]) as mesh:
            report = mesh.validate(check=False)
            self.assertFalse(report.valid)
            self.assertEqual(report.issues[cagekit.MeshIssue.INDEX_OUT_OF_RANGE], 1)
            self.assertIn("face 1 refers to vertex 9000 but the mesh has 8 vertices", report.message)
            with self.assertRaises(cagekit.InvalidMeshError) as caught:
                cagekit.Hierarchy(mesh)
            self.assertIn("9000", str(caught.exception))

    def test_the_message_is_per_context(self):
        ctx = cagekit.Context()
        with self.assertRaises(cagekit.ParseError):
            cagekit.Mesh.from_bytes(b"f 1 2 3\n", "obj", context=ctx)
        self.assertIn(":1", ctx.last_error_message())
        other = cagekit.Context()
        self.assertEqual(other.last_error_message(), "")
        ctx.close()
        other.close()

    def test_measure_error_of_an_identical_mesh_is_zero(self):
        positions, triangles = sphere()
        with cagekit.Mesh.from_arrays(positions, triangles) as a, cagekit.Mesh.from_arrays(positions, triangles) as b:
            error = a.measure_error(b)
            self.assertLess(error.hausdorff_sym_rel, 1e-12)


if __name__ == "__main__":
    unittest.main()
