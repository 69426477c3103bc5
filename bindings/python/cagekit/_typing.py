# SPDX-License-Identifier: GPL-3.0-or-later
"""Type aliases shared by the annotations of the package (typing only: no behaviour)."""
from __future__ import annotations

import os
import sys
from typing import Any, Union

# A file path as the functions that read or write files take it (os.fsencode(os.fspath(path))).
StrPath = Union[str, bytes, os.PathLike]
# Bytes read from memory: any object with the buffer protocol.
Buffer = Union[bytes, bytearray, memoryview]


class _Loaded:
    """A module of the package as annotations name it at run time: attribute lookups go to the
    module in sys.modules (`import cagekit` has loaded every module by the time anything reads
    annotations), so that an annotation may name a class of a module that imports this one
    (Handle.context -> context.Context) without an import, deferred or cyclic. Type checkers
    see the module itself (imported under TYPE_CHECKING)."""

    def __init__(self, name: str) -> None:
        self._name = name

    def __getattr__(self, attr: str) -> Any:
        return getattr(sys.modules[self._name], attr)

    def __repr__(self) -> str:
        return "<module %s, for annotations>" % self._name


def loaded(name: str) -> Any:
    """The run-time stand-in of module `name` (a full name: 'cagekit.context') in annotations."""
    return _Loaded(name)
