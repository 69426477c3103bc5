# SPDX-License-Identifier: GPL-3.0-or-later
"""numpy, imported when first needed.

`import cagekit` works without numpy (files, contexts, round trips through bytes); the first
call that takes or returns arrays raises ImportError with the way to install it.

For type checkers `np` and `npt` are numpy and numpy.typing themselves; at run time they are
lazy stand-ins, so that the annotations of the package (np.ndarray, npt.ArrayLike) resolve
through typing.get_type_hints (which imports numpy then) without `import cagekit` importing it."""
from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

MISSING = ("cagekit needs numpy for array input and output: install it with "
           "'apt install python3-numpy' (Debian's /usr/bin/python3) or 'pip install numpy' "
           "(Blender and FreeCAD bundle it)")


class _LazyNumpy:
    _module = None

    def _load(self) -> Any:
        if _LazyNumpy._module is None:
            try:
                _LazyNumpy._module = importlib.import_module("numpy")
            except ImportError as e:
                raise ImportError(MISSING) from e
        return _LazyNumpy._module

    def __getattr__(self, name: str) -> Any:
        return getattr(self._load(), name)


class _LazyNumpyTyping:
    """numpy.typing, imported on first attribute access (for annotations only)."""

    def __getattr__(self, name: str) -> Any:
        _lazy._load()
        return getattr(importlib.import_module("numpy.typing"), name)


_lazy = _LazyNumpy()

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt
else:
    np = _lazy
    npt = _LazyNumpyTyping()


def available() -> bool:
    try:
        _lazy._load()
        return True
    except ImportError:
        return False
