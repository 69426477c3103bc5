#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Installs the cagekit wheel and tests it where it is installed (ctest packaging.wheel.venv and
packaging.wheel.blender), always with CAGEKIT_LIBRARY and PYTHONPATH unset and from a folder where
`import cagekit` cannot pick up the source tree:

    python3 test_wheel_install.py venv    DIST_DIR WORK_DIR REPO_ROOT
    python3 test_wheel_install.py blender DIST_DIR WORK_DIR REPO_ROOT BLENDER

venv:    a fresh `python3 -m venv --system-site-packages WORK_DIR/venv` (numpy from Debian), the wheel
         installed with `pip install --no-deps --no-index`; then, with the venv's python: the load proof
         (packaging/tests/load_proof.py: the bundled libraries are mapped from the venv) and the
         Python test suite (bindings/python/tests) against the installed package.
blender: `pip install --no-deps --no-index --target WORK_DIR/target` (a folder: nothing system-wide),
         then Blender runs packaging/tests/blender_wheel.py with that folder on sys.path (a job on a
         cube, the load proof with the libraries shared with Blender named, the test suite).
Exit 77 (ctest: skipped) with a message when a tool is missing; 1 on any failure."""
import glob
import importlib.util
import os
import shutil
import subprocess
import sys
import sysconfig

SKIP = 77


def run(cmd, **kw):
    print("+ " + " ".join(cmd), flush=True)
    return subprocess.run(cmd, **kw).returncode


def main(argv):
    mode, dist, work, root = argv[1:5]
    wheels = glob.glob(os.path.join(dist, "cagekit-*.whl"))
    if len(wheels) != 1:
        print("expected one wheel in %s (made by packaging.wheel.make / target python_wheel), found %s" % (dist, wheels))
        return 1
    wheel = wheels[0]
    tag = "-py3-none-%s.whl" % sysconfig.get_platform().replace("-", "_").replace(".", "_")
    if not wheel.endswith(tag):
        print("wheel %s: expected the tag %s (ctypes only: any Python 3, this platform)" % (wheel, tag[1:-4]))
        return 1
    env = {k: v for k, v in os.environ.items() if k not in ("CAGEKIT_LIBRARY", "PYTHONPATH", "PYTHONHOME")}
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    env["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"
    suite = os.path.join(root, "bindings", "python", "tests")
    if os.path.isdir(work):
        shutil.rmtree(work)
    cwd = os.path.join(work, "run")  # an empty folder: '' on sys.path finds no cagekit there
    os.makedirs(cwd)

    if mode == "venv":
        if importlib.util.find_spec("venv") is None or importlib.util.find_spec("ensurepip") is None:
            print("SKIP: %s has no venv/ensurepip module (Debian package python3-venv)" % sys.executable)
            return SKIP
        venv = os.path.join(work, "venv")
        if run([sys.executable, "-m", "venv", "--system-site-packages", venv], env=env):
            return 1
        py = os.path.join(venv, "bin", "python")
        if run([py, "-m", "pip", "install", "-q", "--no-deps", "--no-index", wheel], env=env, cwd=cwd):
            return 1
        checks = [
            ([py, os.path.join(root, "packaging", "tests", "load_proof.py")],
             dict(env, CAGEKIT_EXPECT_PREFIX=venv)),
            ([py, "-m", "unittest", "discover", "-s", suite, "-t", suite],
             dict(env, CAGEKIT_TEST_INSTALLED="1")),
        ]
        failed = 0
        for cmd, e in checks:
            failed += run(cmd, env=e, cwd=cwd) != 0
        code = "import cagekit, sys; print(cagekit.__file__); sys.exit(not cagekit.__file__.startswith(sys.prefix))"
        failed += run([py, "-c", code], env=env, cwd=cwd) != 0
        return 1 if failed else 0

    if mode == "blender":
        blender = argv[5] if len(argv) > 5 else shutil.which("blender")
        if not blender or not os.path.exists(blender):
            print("SKIP: no blender executable")
            return SKIP
        if importlib.util.find_spec("pip") is None:
            print("SKIP: %s has no pip (Debian package python3-pip)" % sys.executable)
            return SKIP
        target = os.path.join(work, "target")
        if run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--no-index", "--target", target, wheel],
               env=env, cwd=cwd):
            return 1
        script = os.path.join(root, "packaging", "tests", "blender_wheel.py")
        return 1 if run([blender, "-b", "--factory-startup", "--python-exit-code", "1", "--python", script, "--",
                         target, "--suite", suite], env=env, cwd=cwd) else 0

    print("unknown mode %s" % mode)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
