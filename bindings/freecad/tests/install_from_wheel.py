# SPDX-License-Identifier: GPL-3.0-or-later
"""Installs the workbench into a scratch FreeCAD user folder the way a user does it without the build
tree (the ctest fixture of freecad.wheel):

    /usr/bin/python3 install_from_wheel.py USER_HOME DIST REPO

DIST: the folder with the one cagekit-*.whl (build/python_wheel/dist, made by the python_wheel target).

- USER_HOME (FREECAD_USER_HOME of the test) is emptied;
- USER_HOME/Mod/CageKit gets what the Addon Manager clones from this repository that FreeCAD reads:
  the root package.xml (its workbench's <subdirectory> is bindings/freecad/CageKit) and that folder,
  without any cagekit package inside;
- the cagekit wheel is installed with `pip install --no-deps --target USER_HOME/AdditionalPythonPackages`
  (what the Addon Manager does for an addon's Python dependencies; FreeCAD 0.20 puts that folder on
  sys.path at start-up). Nothing is installed system-wide.
"""
import glob
import os
import shutil
import subprocess
import sys


def main(home, dist, repo):
    wheels = sorted(glob.glob(os.path.join(dist, "cagekit-*.whl")))
    if len(wheels) != 1:
        sys.exit("install_from_wheel: want one cagekit-*.whl in %s, found %d (build the python_wheel target)"
                 % (dist, len(wheels)))
    wheel = wheels[0]
    shutil.rmtree(home, ignore_errors=True)
    mod = os.path.join(home, "Mod", "CageKit")
    os.makedirs(mod)
    shutil.copy2(os.path.join(repo, "package.xml"), mod)
    shutil.copytree(os.path.join(repo, "bindings", "freecad", "CageKit"),
                    os.path.join(mod, "bindings", "freecad", "CageKit"),
                    ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "cagekit"))
    target = os.path.join(home, "AdditionalPythonPackages")
    env = dict(os.environ)
    for var in ("CAGEKIT_LIBRARY", "PYTHONPATH"):
        env.pop(var, None)
    subprocess.run([sys.executable, "-m", "pip", "install", "--no-deps", "--no-index", "--disable-pip-version-check",
                    "--quiet", "--target", target, wheel], check=True, env=env)
    print("install_from_wheel: workbench in %s, cagekit wheel in %s" % (mod, target))


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit("usage: install_from_wheel.py USER_HOME DIST REPO")
    main(*sys.argv[1:])
