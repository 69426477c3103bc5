# SPDX-License-Identifier: GPL-3.0-or-later
"""cagekit.render / render_png / RenderScene: pictures of generated scans and cages (issue 24).

Drawing needs a headless EGL display (Mesa llvmpipe in CI); the tests that draw skip with the
SDK's message when none can be made. The picture's PNG is decoded with tests/c/png_check.py."""
import os
import sys
import tempfile
import unittest

import numpy as np

import support
from support import CUBE, CUBE_EDGES, CUBE_QUADS, HandleCheck

import cagekit

sys.path.insert(0, os.path.join(support.HERE, "..", "..", "..", "tests", "c"))
import png_check  # noqa: E402

CREASE = np.array([230, 38, 140])   # the default crease colour (0.90, 0.15, 0.55)
YELLOW = np.array([253, 231, 37])   # viridis' last colour (the legend's top)


def count_color(picture, rgb):
    return int(np.sum(np.all(np.abs(picture[..., :3].astype(int) - rgb) <= 1, axis=-1)))


def covered(picture):
    """Share of pixels that are not the white background."""
    return float(np.mean(np.any(picture[..., :3] != 255, axis=-1)))


def draw_or_skip(test, function, *args, **kwargs):
    try:
        return function(*args, **kwargs)
    except cagekit.UnsupportedFeatureError as e:
        test.skipTest("no headless GL here: %s" % e)


class Render(HandleCheck):
    def setUp(self):
        super().setUp()
        positions, triangles = support.grid_cube(8, noise=0.01, seed=24)
        self.scan = cagekit.Mesh.from_arrays(positions, triangles)
        self.cage = cagekit.Cage.from_arrays(CUBE, CUBE_QUADS, creases=CUBE_EDGES)
        self.smooth = cagekit.Cage.from_arrays(CUBE, CUBE_QUADS)

    def tearDown(self):
        for obj in (self.scan, self.cage, self.smooth):
            obj.close()
        super().tearDown()

    def test_size_class_and_coverage_of_every_column(self):
        pic = draw_or_skip(self, cagekit.render, [self.scan, self.cage, ("cage", self.smooth)], size=(480, 200))
        self.assertIsInstance(pic, np.ndarray)
        self.assertIsInstance(pic, cagekit.Picture)
        self.assertEqual((pic.shape, pic.dtype), ((200, 480, 4), np.uint8))
        for k in range(3):
            share = covered(pic[:, k * 160:(k + 1) * 160])
            self.assertTrue(0.05 < share < 0.8, "column %d: %.3f covered" % (k, share))

    def test_creases_colour_exactly_when_asked(self):
        with_creases = draw_or_skip(self, cagekit.render, self.cage, size=(240, 240), creases=True, wire=True)
        without = cagekit.render(self.cage, size=(240, 240), wire=True)
        self.assertGreater(count_color(with_creases, CREASE), 100)
        self.assertEqual(count_color(without, CREASE), 0)
        # A per-item option overrides the call's.
        off = cagekit.render((self.cage, {"creases": False}), size=(240, 240), creases=True)
        self.assertEqual(count_color(off, CREASE), 0)

    def test_error_map_range_is_the_measured_two_sided_maximum(self):
        with cagekit.render_scene([self.smooth], size=(320, 240), error=self.scan) as s:
            info = s.item_info(0)
            values = s.scalars(0)
            self.assertTrue(info.has_scalars)
            self.assertEqual(len(values), info.vertex_count)
            self.assertEqual(info.scalar_max, values.max())
            self.assertEqual(info.scalar_min, values.min())
            # The smooth cube's limit surface lies inside the cube: well away from the scan.
            self.assertGreater(info.scalar_max, 0.05)
            pic = draw_or_skip(self, s.draw)
        self.assertGreaterEqual(count_color(pic, YELLOW), 5)  # the legend bar's top

    def test_repr_png_round_trip_and_render_png(self):
        pic = draw_or_skip(self, cagekit.render, [self.scan, (self.cage, {"error": self.scan, "title": "error"})],
                           size=(200, 120), views="front,iso")
        data = pic._repr_png_()
        self.assertEqual(data[:8], b"\x89PNG\r\n\x1a\n")
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "pic.png")
            again = cagekit.render_png(path, [self.scan, (self.cage, {"error": self.scan, "title": "error"})],
                                       size=(200, 120), views=["front", "iso"])
            np.testing.assert_array_equal(again, pic)  # identical input, identical pixels
            width, height, rows = png_check.read_png(path)
            self.assertEqual((width, height), (200, 120))
            decoded = np.frombuffer(b"".join(rows), dtype=np.uint8).reshape(height, width, 4)
            np.testing.assert_array_equal(decoded, pic)
            with open(path, "rb") as f:
                self.assertEqual(f.read(), data)
        # A slice that is no RGBA image is shown as an array.
        self.assertIsNone(pic[..., 0]._repr_png_())

    def test_one_item_four_views_in_a_grid(self):
        pic = draw_or_skip(self, cagekit.render, self.scan, size=(400, 400), views="front,side,top,iso", labels=False)
        for row in range(2):
            for col in range(2):
                tile = pic[row * 200:(row + 1) * 200, col * 200:(col + 1) * 200]
                ys, xs = np.nonzero(np.any(tile[..., :3] != 255, axis=-1))
                self.assertGreater(len(xs), 0.05 * 200 * 200)
                self.assertLess(abs((xs.min() + xs.max()) / 2 - 100), 20)  # centred in its quadrant
                self.assertLess(abs((ys.min() + ys.max()) / 2 - 100), 20)

    def test_item_forms_and_bad_items(self):
        forms = [self.cage, ("cage", self.cage), (self.cage, {"wire": True}), ("cage", self.cage, {"level": 2}),
                 {"object": self.cage, "title": "x"}, ("deformed", self.scan)]
        with cagekit.render_scene(forms, size=(600, 100)) as s:
            self.assertEqual(len(s), len(forms))
            self.assertEqual([s.item_info(i).column for i in range(len(forms))], list(range(len(forms))))
            self.assertEqual(s.item_info(3).tessellation_level, 2)
            self.assertEqual(s.item_info(5).kind, 2)
        for bad in (["bogus", self.cage], [("cage", self.scan)], [("mesh", self.cage)], [{"object": self.cage,
                                                                                          "colour": 1}], [42], []):
            with self.assertRaises(ValueError, msg=repr(bad)):
                cagekit.render(bad)
        with self.assertRaises(ValueError):
            cagekit.render(self.cage, views="front,back")
        with self.assertRaises(cagekit.LimitExceededError):
            cagekit.render(self.cage, size=(0, 10))

    def test_no_egl_library_is_a_clear_error(self):
        with self.assertRaises(cagekit.UnsupportedFeatureError) as caught:
            cagekit.render(self.cage, size=(64, 64), egl_library="/nonexistent/libEGL-cagekit-test.so.1")
        self.assertIn("libEGL-cagekit-test", str(caught.exception))


if __name__ == "__main__":
    unittest.main()
