# SPDX-License-Identifier: GPL-3.0-or-later
"""LimitSurfaces: the limit surface as one B-spline surface per ptex face (cagekit_limit_surfaces_*)."""
import ctypes
import importlib
import unittest

import numpy as np
from support import CUBE, CUBE_QUADS, CUBE_EDGES, HandleCheck

import cagekit
module = importlib.import_module("cagekit.limit_surfaces")  # cagekit.limit_surfaces is the function


def torus(nu=8, nv=6, major=2.0, minor=0.7):
    """A torus of nu x nv quads: every vertex has valence 4 (its limit surface is one bicubic B-spline)."""
    a = 2 * np.pi * np.arange(nu)[:, None] / nu
    b = 2 * np.pi * np.arange(nv)[None, :] / nv
    x = (major + minor * np.cos(b)) * np.cos(a)
    y = (major + minor * np.cos(b)) * np.sin(a)
    z = minor * np.sin(b) + 0.01 * np.arange(nu)[:, None] + 0 * b
    positions = np.stack([x, y, z], axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    quads = np.stack([i * nv + j, (i + 1) % nu * nv + j, (i + 1) % nu * nv + (j + 1) % nv, i * nv + (j + 1) % nv],
                     axis=-1).reshape(-1, 4)
    return positions, quads


def cox_de_boor(knots, degree, i, x):
    """N_{i,degree}(x) by the textbook recursion (0/0 = 0; x = 1 in the last nonempty span)."""
    if degree == 0:
        last = max(k for k in range(len(knots) - 1) if knots[k] < knots[k + 1])
        return 1.0 if knots[i] <= x < knots[i + 1] or (i == last and x == knots[i + 1]) else 0.0
    a = (x - knots[i]) / (knots[i + degree] - knots[i]) if knots[i + degree] > knots[i] else 0.0
    b = (knots[i + degree + 1] - x) / (knots[i + degree + 1] - knots[i + 1]) if knots[i + degree + 1] > knots[i + 1] \
        else 0.0
    return a * cox_de_boor(knots, degree - 1, i, x) + b * cox_de_boor(knots, degree - 1, i + 1, x)


def by_hand(s, u, v):
    """The point of BSplineSurface s at (u, v), summed term by term."""
    bu = [cox_de_boor(s.knots_u, s.degree_u, i, u) for i in range(s.num_u)]
    bv = [cox_de_boor(s.knots_v, s.degree_v, j, v) for j in range(s.num_v)]
    cp = s.control_points
    return sum(bu[i] * bv[j] * cp[j, i] for i in range(s.num_u) for j in range(s.num_v))


def side_uv(side, t):
    t = np.asarray(t, dtype=np.float64)
    u = np.ones_like(t) if side == 1 else np.zeros_like(t) if side == 3 else t
    v = np.zeros_like(t) if side == 0 else np.ones_like(t) if side == 2 else t
    return np.stack([u, v], axis=1)


def border_row(s, side):
    cp = s.control_points  # [j, i]
    return {0: cp[0, :], 1: cp[:, -1], 2: cp[-1, :], 3: cp[:, 0]}[side]


class LimitSurfaceChecks(HandleCheck):
    def check_surfaces(self, cage, surfaces):
        """Common checks; returns (largest distance to the limit surface on an 11 x 11 grid per
        surface, the number of sides whose border control points equal the neighbour's)."""
        info = surfaces.info
        n = info.surface_count
        self.assertEqual(len(surfaces), n)
        self.assertEqual(n, info.exact_count + info.approximated_count)
        pos = cage.positions
        diag = float(np.linalg.norm(pos.max(0) - pos.min(0)))
        self.assertAlmostEqual(info.bbox_diagonal, diag, delta=1e-12 * diag)
        g = np.linspace(0.0, 1.0, 11)
        uv = np.stack(np.meshgrid(g, g, indexing="ij"), axis=-1).reshape(-1, 2)
        worst, identical, exact = 0.0, 0, 0
        all_surfaces = list(surfaces)
        with cage.surface() as limit:
            self.assertEqual(limit.counts()[0], info.ptex_face_count)
            for k, s in enumerate(all_surfaces):
                exact += s.exact
                self.assertEqual((s.degree_u, s.degree_v), (3, 3))
                for knots, num, p in ((s.knots_u, s.num_u, s.degree_u), (s.knots_v, s.num_v, s.degree_v)):
                    self.assertEqual(knots.shape, (num + p + 1,))
                    np.testing.assert_array_equal(knots[:p + 1], 0.0)
                    np.testing.assert_array_equal(knots[-p - 1:], 1.0)
                    self.assertTrue(np.all(np.diff(knots[p:-p]) > 0), "simple interior knots")
                self.assertEqual(s.control_points.shape, (s.num_v, s.num_u, 3))
                d = np.linalg.norm(s.evaluate(uv) - limit.evaluate(np.full(len(uv), s.ptex_face), uv).position, axis=1)
                self.assertLessEqual(d.max(), s.error * (1 + 1e-9) + 1e-13 * diag)
                worst = max(worst, float(d.max()))
                for side, sd in enumerate(s.sides):
                    self.assertEqual(sd.kind == cagekit.BorderKind.BOUNDARY, len(sd.neighbours) == 0)
                    for nb in sd.neighbours:
                        o = all_surfaces[nb.surface]
                        self.assertEqual(o.sides[nb.side].kind, sd.kind)
                        back = [(b.t0, b.t1) for b in o.sides[nb.side].neighbours if b.surface == k and b.side == side]
                        self.assertEqual(len(back), 1, "neighbour relation symmetric")
                        self.assertAlmostEqual(min(back[0]), min(nb.n0, nb.n1), delta=1e-15)
                        self.assertAlmostEqual(max(back[0]), max(nb.n0, nb.n1), delta=1e-15)
                        q = np.linspace(0.0, 1.0, 9)
                        mine = s.evaluate(side_uv(side, nb.t0 + q * (nb.t1 - nb.t0)))
                        theirs = o.evaluate(side_uv(nb.side, nb.n0 + q * (nb.n1 - nb.n0)))
                        self.assertLessEqual(np.abs(mine - theirs).max(), 1e-12 * diag, "shared borders meet")
                        if (len(sd.neighbours) == 1 and (nb.t0, nb.t1) == (0.0, 1.0) and abs(nb.n1 - nb.n0) == 1.0 and
                                len(border_row(s, side)) == len(border_row(o, nb.side))):
                            theirs_row = border_row(o, nb.side)
                            np.testing.assert_array_equal(border_row(s, side),
                                                          theirs_row if nb.n1 > nb.n0 else theirs_row[::-1])
                            identical += 1
        self.assertEqual(exact, info.exact_count)
        np.testing.assert_array_equal(np.diff([s.ptex_face for s in all_surfaces]) > 0, True)
        return worst, identical


class LimitSurfacesOfGeneratedCages(LimitSurfaceChecks):
    def test_a_regular_torus_is_exact(self):
        positions, quads = torus()
        with cagekit.Cage.from_arrays(positions, quads) as cage, cagekit.limit_surfaces(cage) as surfaces:
            info = surfaces.info
            self.assertEqual((info.surface_count, info.ptex_face_count, info.exact_count), (48, 48, 48))
            self.assertEqual((info.approximated_count, info.over_tolerance_count), (0, 0))
            self.assertLessEqual(info.max_error_rel, 1e-12)
            self.assertLess(info.max_normal_jump_deg, 1e-6)
            worst, identical = self.check_surfaces(cage, surfaces)
            self.assertLessEqual(worst, 1e-12 * info.bbox_diagonal)
            self.assertEqual(identical, 4 * 48)
            # the module's evaluation is the textbook Cox-de Boor sum
            s = surfaces[5]
            for u, v in ((0.0, 0.0), (0.3, 0.71), (1.0, 0.5), (1.0, 1.0)):
                np.testing.assert_allclose(s.evaluate([u, v])[0], by_hand(s, u, v), rtol=0, atol=1e-14)
            # and the limit surface at ptex points, evaluated with the textbook sum
            with cage.surface() as limit:
                for k in (0, 17, 47):
                    s = surfaces[k]
                    for u, v in ((0.12, 0.9), (0.5, 0.5), (0.97, 0.03)):
                        y = limit.evaluate([s.ptex_face], [[u, v]]).position[0]
                        self.assertLessEqual(np.linalg.norm(by_hand(s, u, v) - y), 1e-12 * info.bbox_diagonal)

    def test_a_cube_is_approximated_within_the_tolerance(self):
        with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS) as cage, cagekit.LimitSurfaces(cage) as surfaces:
            info = surfaces.info
            self.assertEqual((info.surface_count, info.exact_count, info.approximated_count), (6, 0, 6))
            self.assertEqual(info.over_tolerance_count, 0)
            self.assertGreater(info.max_error, 0)
            self.assertLessEqual(info.max_error, info.tolerance)
            self.assertAlmostEqual(info.tolerance, 1e-4 * info.bbox_diagonal, delta=1e-15)
            self.assertEqual(info.max_error, max(s.error for s in surfaces))
            self.assertEqual(info.max_crease_angle_deg, 0.0)
            self.assertLess(info.max_normal_jump_deg, 1.0)
            worst, identical = self.check_surfaces(cage, surfaces)
            self.assertLessEqual(worst, info.tolerance)
            self.assertEqual(identical, 4 * 6)
            for s in surfaces:
                self.assertEqual(s.cage_face, s.ptex_face)
                self.assertEqual([sd.kind for sd in s.sides], [cagekit.BorderKind.SMOOTH] * 4)
                self.assertLessEqual(max(sd.max_normal_jump_deg for sd in s.sides), info.max_normal_jump_deg)
            # between the measured samples: within twice the error
            rng = np.random.default_rng(7)
            uv = rng.random((500, 2))
            with cage.surface() as limit:
                for s in surfaces:
                    d = np.linalg.norm(s.evaluate(uv) - limit.evaluate(np.full(500, s.ptex_face), uv).position, axis=1)
                    self.assertLessEqual(d.max(), 2.0 * s.error)

    def test_a_creased_cube_has_c0_borders(self):
        with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS, creases=CUBE_EDGES) as cage, \
                cagekit.LimitSurfaces(cage) as surfaces:
            info = surfaces.info
            self.assertEqual((info.exact_count, info.approximated_count), (6, 0))
            self.assertAlmostEqual(info.max_crease_angle_deg, 90.0, delta=1e-9)
            self.assertEqual(info.max_normal_jump_deg, 0.0)
            worst, _ = self.check_surfaces(cage, surfaces)
            self.assertLessEqual(worst, 1e-12 * info.bbox_diagonal)
            for s in surfaces:
                self.assertEqual([sd.kind for sd in s.sides], [cagekit.BorderKind.CREASE] * 4)
                for sd in s.sides:
                    self.assertAlmostEqual(sd.max_normal_jump_deg, 90.0, delta=1e-9)

    def test_n_gon_sub_faces_and_boundaries(self):
        # a pyramid: a quad base (1 surface) and 4 triangles (3 sub-faces, so 3 surfaces, each)
        apex = np.array([[0.5, 0.5, 0.8]])
        faces = [0, 3, 2, 1, 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4]
        with cagekit.Cage.from_arrays(np.vstack([CUBE[:4][[0, 1, 3, 2]], apex]), faces,
                                      face_sizes=[4, 3, 3, 3, 3]) as cage, \
                cagekit.LimitSurfaces(cage) as surfaces:
            info = surfaces.info
            self.assertEqual((info.surface_count, info.ptex_face_count, info.over_tolerance_count), (13, 13, 0))
            self.assertLessEqual(info.max_error, info.tolerance)
            self.assertLess(info.max_normal_jump_deg, 1.0)
            worst, _ = self.check_surfaces(cage, surfaces)
            self.assertLessEqual(worst, info.tolerance)
            self.assertEqual([s.cage_face for s in surfaces], [0] + [1] * 3 + [2] * 3 + [3] * 3 + [4] * 3)
            base = surfaces[0]
            sub_face = surfaces[1]
            self.assertEqual(base.num_u - 3, 2 * (sub_face.num_u - 3), "a sub-face is half an edge long")
            for side in base.sides:
                # each side of the base meets two triangle sub-faces, one on each half
                self.assertEqual(side.kind, cagekit.BorderKind.SMOOTH)
                ranges = sorted((nb.t0, nb.t1) for nb in side.neighbours)
                self.assertEqual(ranges, [(0.0, 0.5), (0.5, 1.0)])
                for nb in side.neighbours:
                    self.assertEqual(abs(nb.n1 - nb.n0), 1.0)
                    self.assertNotEqual(surfaces[nb.surface].cage_face, 0)
        # an open 3 x 3 grid: the outer sides are boundaries without neighbours
        grid = np.array([[i, j, 0.1 * ((i * j) % 3)] for j in range(4) for i in range(4)], dtype=np.float64)
        quads = np.array([[j * 4 + i, j * 4 + i + 1, (j + 1) * 4 + i + 1, (j + 1) * 4 + i]
                          for j in range(3) for i in range(3)])
        with cagekit.Cage.from_arrays(grid, quads) as cage, cagekit.LimitSurfaces(cage) as surfaces:
            info = surfaces.info
            self.assertEqual(info.surface_count, 9)
            self.assertGreater(info.exact_count, 0)
            worst, identical = self.check_surfaces(cage, surfaces)
            self.assertLessEqual(worst, info.tolerance)
            kinds = [sd.kind for s in surfaces for sd in s.sides]
            self.assertEqual(kinds.count(cagekit.BorderKind.BOUNDARY), 12)
            self.assertEqual(kinds.count(cagekit.BorderKind.SMOOTH), 24)
            self.assertEqual(identical, 24)
            self.assertTrue(all(sd.max_normal_jump_deg == 0.0 for s in surfaces for sd in s.sides
                                if sd.kind == cagekit.BorderKind.BOUNDARY))

    def test_levels_and_a_coarser_tolerance(self):
        with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS) as cage, \
                cagekit.LimitSurfaces(cage, tolerance=1e-2) as coarse, \
                cagekit.LimitSurfaces(cage, tolerance=1e-5) as fine, \
                cagekit.LimitSurfaces(cage, min_level=2, max_level=2) as fixed:
            self.assertLess(coarse.info.level, fine.info.level)
            self.assertEqual(coarse.info.over_tolerance_count, 0)
            self.assertLessEqual(coarse.info.max_error_rel, 1e-2)
            # 1e-5 is out of reach at the default max_level 5: the surfaces are kept and counted
            self.assertEqual(fine.info.level, 5)
            self.assertGreater(fine.info.over_tolerance_count, 0)
            self.assertEqual(sum(s.error > fine.info.tolerance for s in fine), fine.info.over_tolerance_count)
            self.assertLess(fine.info.max_error, coarse.info.max_error)
            self.assertEqual(fixed.info.level, 2)
            self.assertEqual((fixed[0].num_u, fixed[0].num_v), (4 + 3, 4 + 3))
            self.assertEqual(len(fixed[-1].knots_u), 4 + 7)

    def test_bad_arguments_raise_with_the_sdk_message(self):
        with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS) as cage:
            for tolerance in (0.0, -1e-4, float("nan"), float("inf")):
                with self.assertRaises(cagekit.InvalidArgumentError) as caught:
                    cagekit.LimitSurfaces(cage, tolerance=tolerance)
                self.assertIn("tolerance", str(caught.exception))
            for kwargs, field in (({"max_level": 8}, "max_level"), ({"max_level": 0}, "max_level"),
                                  ({"min_level": 0}, "min_level"), ({"min_level": 4, "max_level": 3}, "min_level")):
                with self.assertRaises(cagekit.InvalidArgumentError) as caught:
                    cagekit.LimitSurfaces(cage, **kwargs)
                self.assertIn(field, str(caught.exception))
            with cagekit.LimitSurfaces(cage, tolerance=1e-3) as surfaces:
                for index in (6, -7):
                    with self.assertRaises(cagekit.InvalidArgumentError):
                        surfaces[index]
                # the C calls themselves: index and side out of range, two-call SIZE_INSUFFICIENT
                call, h, count = surfaces.context._call, surfaces._handle, ctypes.c_uint32()
                with self.assertRaises(cagekit.InvalidArgumentError):
                    call(module.lib.cagekit_limit_surfaces_get_control_points, h, 6, 0, ctypes.byref(count), None)
                with self.assertRaises(cagekit.InvalidArgumentError):
                    call(module.lib.cagekit_limit_surfaces_get_neighbours, h, 0, 4, 0, ctypes.byref(count), None)
                with self.assertRaises(cagekit.InvalidArgumentError):
                    call(module.lib.cagekit_limit_surfaces_get_knots, h, 0, 2, 0, ctypes.byref(count), None)
                call(module.lib.cagekit_limit_surfaces_get_knots, h, 0, 1, 0, ctypes.byref(count), None)
                self.assertEqual(count.value, len(surfaces[0].knots_v))
                buffer = np.zeros(count.value, dtype=np.float64)
                with self.assertRaises(cagekit.SizeInsufficientError):
                    call(module.lib.cagekit_limit_surfaces_get_knots, h, 0, 1, count.value - 1, ctypes.byref(count),
                         buffer.ctypes.data)
                self.assertEqual(count.value, len(surfaces[0].knots_v))
            with self.assertRaises(ValueError):
                surfaces[3]  # closed (not read before)

    def test_progress_and_cancel(self):
        stages = []
        with cagekit.Context(progress=lambda stage, f: stages.append((stage, f))) as ctx:
            with cagekit.Cage.from_arrays(CUBE, CUBE_QUADS, context=ctx) as cage:
                with cagekit.LimitSurfaces(cage) as surfaces:
                    self.assertEqual(len(surfaces), 6)
                self.assertIn("limit B-spline surfaces", {s for s, _ in stages})
                ctx.progress = lambda stage, f: False
                with self.assertRaises(cagekit.CancelledError):
                    cagekit.LimitSurfaces(cage)


if __name__ == "__main__":
    unittest.main()
