# SPDX-License-Identifier: GPL-3.0-or-later
"""numpy, imported when first needed.

`import cagekit` works without numpy (files, contexts, round trips through bytes); the first
call that takes or returns arrays raises ImportError with the way to install it."""
import importlib

MISSING = ("cagekit needs numpy for array input and output: install it with "
           "'apt install python3-numpy' (Debian's /usr/bin/python3) or 'pip install numpy' "
           "(Blender and FreeCAD bundle it)")


class _LazyNumpy:
    _module = None

    def _load(self):
        if _LazyNumpy._module is None:
            try:
                _LazyNumpy._module = importlib.import_module("numpy")
            except ImportError as e:
                raise ImportError(MISSING) from e
        return _LazyNumpy._module

    def __getattr__(self, name):
        return getattr(self._load(), name)


np = _LazyNumpy()


def available():
    try:
        np._load()
        return True
    except ImportError:
        return False
