# SPDX-License-Identifier: GPL-3.0-or-later
"""The cagekit wheel inside Blender's Python (ctest packaging.wheel.blender):

    blender -b --factory-startup --python-exit-code 1 --python blender_wheel.py -- TARGET [--suite TESTS_DIR]

TARGET is a folder the wheel was installed into with `pip install --no-deps --target TARGET`
(nothing system-wide). It is put first on sys.path; then `import cagekit` must come from it, a real
job runs on a generated cube (Catmull-Clark subdivision to counts, the limit surface evaluated, a
fit of the subdivided cube back to a 6-face cage), and the load proof lists which bundled libraries
were loaded from the wheel and which are shared with Blender (Debian's Blender links OpenSubdiv,
GMP, libpng, zlib, libgomp itself: a SONAME is loaded once per process, so Blender's copies are
used). With --suite, the Python test suite (bindings/python/tests) then runs inside Blender against
the installed package. Any failure raises, so Blender exits with status 1."""
import os
import sys
import unittest

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
TARGET = os.path.realpath(argv[0])
SUITE = argv[argv.index("--suite") + 1] if "--suite" in argv else None
HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import load_proof  # noqa: E402

for var in ("CAGEKIT_LIBRARY", "PYTHONPATH"):
    if os.environ.get(var):
        raise RuntimeError("%s is set (%s): the test must run without it" % (var, os.environ[var]))

before = load_proof.mapped()
sys.path.insert(0, TARGET)
import bpy  # noqa: E402
import cagekit  # noqa: E402
import numpy as np  # noqa: E402

print("Blender %s, Python %s" % (bpy.app.version_string, sys.version.split()[0]))
print("cagekit %s imported from %s, library %s" % (cagekit.version(), cagekit.__file__, cagekit.library_path))
if not os.path.realpath(cagekit.__file__).startswith(TARGET + os.sep):
    raise AssertionError("cagekit imported from %s, not from the --target folder %s" % (cagekit.__file__, TARGET))
if not os.path.realpath(cagekit.library_path).startswith(TARGET + os.sep):
    raise AssertionError("libcagekit loaded from %s, not from the wheel" % cagekit.library_path)

# A real job on a generated cube: two levels of subdivision, the limit surface, a fit back.
cube = cagekit.Mesh.from_arrays(
    np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 1, 1]], float),
    np.array([[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]], np.uint32))
cage = cagekit.Cage(cube)
fine = cage.subdivide(2).mesh()
if fine.counts() != (98, 96, 384):
    raise AssertionError("cube subdivided twice: %s, expected (98, 96, 384)" % (fine.counts(),))
limit, normals = cage.limit_points()
radius = np.linalg.norm(limit - 0.5, axis=1)
if limit.shape != (8, 3) or not (np.all(radius < np.sqrt(3) / 2) and np.all(radius > 0.25)):
    raise AssertionError("limit points of the cube not inside it: %s" % radius)
fitted, report = cagekit.fit(cage, fine, max_passes=2)
rms = [p.rms_rel for p in report.passes]
if fitted.mesh().counts()[:2] != (8, 6) or not all(b <= a + 1e-12 for a, b in zip(rms, rms[1:])):
    raise AssertionError("fit: counts %s, rms %s" % (fitted.mesh().counts(), rms))
print("job: cube subdivided to %s, limit radii %.3f..%.3f, fit rms %s" % (
    fine.counts(), radius.min(), radius.max(), ["%.3g" % r for r in rms]))

failures = load_proof.check(os.path.dirname(cagekit.__file__), before, host="Blender")
if failures:
    raise AssertionError("load proof failed: %s" % failures)
print("load proof: libraries listed as shared are Blender's own copies (same SONAME, loaded before the import); "
      "all the others come from the wheel")

if SUITE:
    os.environ["CAGEKIT_TEST_INSTALLED"] = "1"
    sys.path.insert(0, SUITE)
    tests = unittest.defaultTestLoader.discover(SUITE, top_level_dir=SUITE)
    result = unittest.TextTestRunner(verbosity=1, stream=sys.stdout).run(tests)
    if not result.wasSuccessful():
        raise AssertionError("Python test suite inside Blender: %d failures, %d errors"
                             % (len(result.failures), len(result.errors)))
print("packaging.wheel.blender: OK")
