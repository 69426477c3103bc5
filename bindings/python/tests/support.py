# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared helpers of the cagekit Python tests: generated meshes and the shared real meshes."""
import math
import os
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
# CAGEKIT_TEST_INSTALLED=1 (the packaging.* tests): the package under test is the installed wheel,
# found on the interpreter's own sys.path; else bindings/python, the source tree.
INSTALLED = os.environ.get("CAGEKIT_TEST_INSTALLED") == "1"
if not INSTALLED:
    sys.path.insert(0, os.path.dirname(HERE))  # bindings/python: the package under test

import numpy as np  # noqa: E402  (the tests need numpy; the package imports without it)

import cagekit  # noqa: E402

if INSTALLED and os.path.realpath(cagekit.__file__).startswith(os.path.realpath(os.path.dirname(HERE)) + os.sep):
    raise ImportError("CAGEKIT_TEST_INSTALLED=1 but cagekit was imported from the source tree: %s" % cagekit.__file__)

CUBE = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 1, 1]],
                dtype=np.float64)
CUBE_QUADS = np.array([[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]],
                      dtype=np.uint32)
CUBE_EDGES = np.array([[0, 1], [2, 3], [4, 5], [6, 7], [0, 2], [1, 3], [4, 6], [5, 7], [0, 4], [1, 5], [2, 6],
                       [3, 7]], dtype=np.uint32)


def sphere(rings=12, segments=24, radius=0.75, centre=(0.5, 0.5, 0.5)):
    """A lat-long triangle sphere around the unit cube's centre (as tests/c/test_capi.c)."""
    pts = [(0.0, 0.0, radius)]
    for r in range(1, rings):
        theta = math.pi * r / rings
        for k in range(segments):
            phi = 2 * math.pi * k / segments
            pts.append((radius * math.sin(theta) * math.cos(phi), radius * math.sin(theta) * math.sin(phi),
                        radius * math.cos(theta)))
    pts.append((0.0, 0.0, -radius))
    south = len(pts) - 1
    tris = []
    for k in range(segments):
        tris.append((0, 1 + k, 1 + (k + 1) % segments))
    for r in range(1, rings - 1):
        for k in range(segments):
            k1 = (k + 1) % segments
            a, b = 1 + (r - 1) * segments + k, 1 + (r - 1) * segments + k1
            tris += [(a, a + segments, b + segments), (a, b + segments, b)]
    base = 1 + (rings - 2) * segments
    for k in range(segments):
        tris.append((south, base + (k + 1) % segments, base + k))
    return np.array(pts) + np.array(centre), np.array(tris, dtype=np.uint32)


def grid_cube(n=4, noise=0.0, seed=1):
    """The unit cube with each side an n x n grid split into 2 n^2 triangles (welded, outward);
    optional normal noise on the interior vertices of the sides."""
    index, pts, tris = {}, [], []

    def vertex(p):
        key = tuple(int(round(c * n)) for c in p)
        if key not in index:
            index[key] = len(pts)
            pts.append(p)
        return index[key]

    for q in CUBE_QUADS:
        c = CUBE[q]
        for i in range(n):
            for j in range(n):
                def at(a, b):
                    u, v = a / n, b / n
                    return tuple((1 - u) * (1 - v) * c[0] + u * (1 - v) * c[1] + u * v * c[2] + (1 - u) * v * c[3])
                a, b, cc, d = vertex(at(i, j)), vertex(at(i + 1, j)), vertex(at(i + 1, j + 1)), vertex(at(i, j + 1))
                tris += [(a, b, cc), (a, cc, d)]
    pts = np.array(pts, dtype=np.float64)
    if noise:
        rng = np.random.default_rng(seed)
        inside = np.sum((pts > 1e-9) & (pts < 1 - 1e-9), axis=1) == 2  # inside a side, off its edges
        pts[inside] += rng.normal(0, noise, size=(int(inside.sum()), 3))
    return pts, np.array(tris, dtype=np.uint32)


def shared_mesh(name):
    """Path of a shared real mesh, or skips the test with a message when it is absent."""
    folder = os.environ.get("CAGEKIT_SHARED_MESHES") or os.path.join(HERE, "..", "..", "..", "..", "shared",
                                                                      "meshes")
    path = os.path.join(folder, name)
    if not os.path.exists(path):
        raise unittest.SkipTest("shared mesh %s absent (set CAGEKIT_SHARED_MESHES)" % path)
    return path


cagekit.default_context()  # made once here, so that the handle counts below do not see it


class HandleCheck(unittest.TestCase):
    """Fails a test that leaves CageKit handles behind (after collecting its garbage)."""

    def setUp(self):
        import gc
        gc.collect()
        self._handles_before = cagekit.live_handles()

    def tearDown(self):
        import gc
        gc.collect()
        self.assertEqual(cagekit.live_handles(), self._handles_before, "CageKit handles leaked by the test")
