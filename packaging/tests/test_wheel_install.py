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
         Python test suite (bindings/python/tests) against the installed package; the bundled CLI:
         the console script `cagekit`, its libraries resolved inside the venv, and a
         cagekit.batch run of one generated scan that finds it with CAGEKIT_CLI unset.
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


def write_test_scan(path):
    """A closed 8x8x8-cell box surface as a triangle OBJ (384 quads, 768 triangles)."""
    n, verts, index, faces = 8, [], {}, []

    def vid(p):
        if p not in index:
            index[p] = len(verts)
            verts.append(p)
        return index[p] + 1

    for axis in range(3):
        for side in (0, n):
            for i in range(n):
                for j in range(n):
                    quad = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = [0, 0, 0]
                        p[axis], p[(axis + 1) % 3], p[(axis + 2) % 3] = side, i + di, j + dj
                        quad.append(vid(tuple(p)))
                    if side == 0:
                        quad.reverse()
                    faces += [(quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])]
    with open(path, "w") as f:
        f.writelines("v %d %d %d\n" % v for v in verts)
        f.writelines("f %d %d %d\n" % t for t in faces)


def check_bundled_cli(venv, py, env, cwd):
    """The CLI the wheel bundles: the console script runs it, its libraries resolve inside the venv,
    and cagekit.batch (which finds it without CAGEKIT_CLI or PATH) runs a scan through it."""
    failed = 0
    env = dict(env, PATH=os.path.join(venv, "bin") + os.pathsep + "/usr/bin:/bin")
    env.pop("CAGEKIT_CLI", None)
    script = os.path.join(venv, "bin", "cagekit")
    r = subprocess.run([script, "version"], env=env, cwd=cwd, capture_output=True, text=True)
    print("+ %s version -> %d: %s" % (script, r.returncode, r.stdout.strip()), flush=True)
    if r.returncode != 0 or not r.stdout.strip():
        print("FAIL: the wheel's console script `cagekit version`: %s" % r.stderr.strip())
        failed += 1
    code = ("import cagekit._cli as c; print(c.bundled_cli())")
    bundled = subprocess.run([py, "-c", code], env=env, cwd=cwd, capture_output=True, text=True).stdout.strip()
    if not bundled.startswith(venv + os.sep):
        print("FAIL: the bundled CLI %r is not inside the venv %s" % (bundled, venv))
        return failed + 1
    ldd = subprocess.run(["ldd", bundled], capture_output=True, text=True).stdout
    for line in ldd.splitlines():
        if "not found" in line or ("libcagekit" in line and venv + os.sep not in line):
            print("FAIL: the bundled CLI's library %s" % line.strip())
            failed += 1
    scan = os.path.join(cwd, "box.obj")
    write_test_scan(scan)
    out = os.path.join(cwd, "batch")
    code = ("import sys, cagekit.batch as b\n"
            "cli = b.find_cli()\n"
            "assert cli == %r, cli\n"
            "rows = b.run([%r], %r, options={'faces': 60}, jobs=1, progress=False, timeout=300)\n"
            "rows = rows.to_dict('records') if hasattr(rows, 'to_dict') else rows\n"
            "print(rows[0]['status'], rows[0]['faces'], rows[0]['message'])\n"
            "sys.exit(rows[0]['status'] != 'ok' or not rows[0]['faces'])\n" % (bundled, scan, out))
    if run([py, "-c", code], env=env, cwd=cwd) != 0:
        print("FAIL: cagekit.batch.run through the bundled CLI")
        failed += 1
    elif not os.path.isfile(os.path.join(out, "box", "cage.obj")):
        print("FAIL: no %s after the batch" % os.path.join(out, "box", "cage.obj"))
        failed += 1
    return failed


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
        failed += check_bundled_cli(venv, py, env, cwd)
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
