#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Builds the cagekit wheel from a build tree (CMake target python_wheel; the ctest fixture
packaging.wheel.make runs it too):

    python3 make_wheel.py SOURCE_DIR LIBRARY SONAME OUT_DIR [CLI]

SOURCE_DIR is bindings/python (pyproject.toml, setup.py, README.md, cagekit/). It is copied to
OUT_DIR/stage (nothing is written into the source tree), libcagekit, the `cagekit` CLI (CLI, as
stage/cagekit/bin/cagekit: the console script `cagekit` of the wheel runs it, and cagekit.batch's
workers find it there) and their non-system libraries are bundled into stage/cagekit by
packaging/bundle_libs.py, and the wheel is built offline with
the running interpreter's pip, setuptools and wheel (Debian's):
    python3 -m pip wheel --no-build-isolation --no-deps --no-index OUT_DIR/stage -w OUT_DIR/dist
OUT_DIR/dist then holds exactly one wheel, cagekit-VERSION-py3-none-PLATFORM.whl; its path is printed.
"""
import glob
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bundle_libs  # noqa: E402


def main(argv):
    if len(argv) not in (5, 6):
        sys.stderr.write("usage: make_wheel.py SOURCE_DIR LIBRARY SONAME OUT_DIR [CLI]\n")
        return 2
    source, library, soname, out = argv[1:5]
    executables = argv[5:]
    for path in [library] + executables:
        if not os.path.exists(path):
            sys.stderr.write("make_wheel.py: %s not built\n" % path)
            return 1
    stage, dist = os.path.join(out, "stage"), os.path.join(out, "dist")
    for d in (stage, dist):
        if os.path.isdir(d):
            shutil.rmtree(d)
    os.makedirs(dist)
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc", "*.egg-info", "build")
    shutil.copytree(os.path.join(source, "cagekit"), os.path.join(stage, "cagekit"), ignore=ignore)
    for name in ("pyproject.toml", "setup.py", "README.md"):
        shutil.copyfile(os.path.join(source, name), os.path.join(stage, name))
    try:
        bundled = bundle_libs.bundle(library, os.path.join(stage, "cagekit"), soname, executables)
    except (RuntimeError, OSError, subprocess.CalledProcessError) as e:
        sys.stderr.write("make_wheel.py: %s\n" % e)
        return 1
    print("make_wheel.py: bundled " + ", ".join(bundled))
    cmd = [sys.executable, "-m", "pip", "wheel", "--no-build-isolation", "--no-deps", "--no-index",
           "--disable-pip-version-check", "-q", stage, "-w", dist]
    r = subprocess.run(cmd, env=dict(os.environ, PYTHONDONTWRITEBYTECODE="1"))
    if r.returncode != 0:
        sys.stderr.write("make_wheel.py: pip wheel failed (%d): %s\n" % (r.returncode, " ".join(cmd)))
        return 1
    wheels = glob.glob(os.path.join(dist, "*.whl"))
    if len(wheels) != 1:
        sys.stderr.write("make_wheel.py: expected one wheel in %s, found %s\n" % (dist, wheels))
        return 1
    print(wheels[0])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
