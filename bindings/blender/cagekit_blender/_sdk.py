# SPDX-License-Identifier: GPL-3.0-or-later
"""Finds the `cagekit` Python package.

In the add-on zip (CMake target `blender_addon_zip`) the package is bundled inside the add-on
folder (cagekit_blender/cagekit/, with libcagekit.so.2 next to its files, which is the package's
own second lookup place); that layout is valid both for a Blender 3.x add-on and for a 4.2+
extension (whose code must live in one package). From a source tree, `cagekit` is imported from
sys.path (bindings/python) and the library found through CAGEKIT_LIBRARY.

The import is done on first use, not at add-on registration: when libcagekit cannot be loaded
the add-on still registers and every operator reports the ImportError's message.
"""
import importlib
import os

_module = None


def sdk():
    """The cagekit module (ImportError with the package's message when it cannot be loaded)."""
    global _module
    if _module is None:
        here = os.path.dirname(os.path.abspath(__file__))
        if os.path.isfile(os.path.join(here, "cagekit", "__init__.py")):
            _module = importlib.import_module(__package__ + ".cagekit")
        else:
            _module = importlib.import_module("cagekit")
    return _module

