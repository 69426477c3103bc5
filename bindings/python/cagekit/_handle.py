# SPDX-License-Identifier: GPL-3.0-or-later
"""The base of every Python object that owns a CageKit handle (one C reference).

The reference is released deterministically by close() or a `with` block, and otherwise by
__del__ when the object is collected. live_handles() counts the handles Python holds, for
tests and leak checks."""
from __future__ import annotations

import ctypes
import threading
from typing import TYPE_CHECKING, Any, Callable, Literal, Optional, Type, TypeVar, cast

from . import _lib, _typing

if TYPE_CHECKING:
    from . import context as _context_module
else:
    _context_module = _typing.loaded("cagekit.context")  # context.py imports this module

_H = TypeVar("_H", bound="Handle")

_live = 0
_live_lock = threading.Lock()


def live_handles() -> int:
    """Number of CageKit handles currently owned by Python objects of this package."""
    return _live


class Handle:
    _release_name: Optional[str] = None  # the cagekit_*_release function of the type
    _functions: Any = None  # where _release_name is declared: None for _lib.lib, else a module's _lib.Functions
    _kind = "handle"
    _ptr: Optional[int]
    _context: _context_module.Context  # None only in a Context itself, whose `context` is itself

    @classmethod
    def _wrap(cls: Type[_H], ptr: Optional[int], context: Any) -> _H:
        """An object of this class around `ptr` (one reference), bypassing the public __init__."""
        obj = cls.__new__(cls)
        Handle.__init__(obj, ptr, context)
        return obj

    @classmethod
    def _make(cls: Type[_H], ctx: Any, fn: Any, *args: Any) -> _H:
        """Calls fn(*args, &out) through the context `ctx` and wraps *out."""
        out = ctypes.c_void_p()
        ctx._call(fn, *args, ctypes.byref(out), outs=[(out, cls._release())])
        return cls._wrap(out.value, ctx)

    @classmethod
    def _release(cls) -> Callable[..., Any]:
        """The declared cagekit_*_release function of the type."""
        return getattr(_lib.lib if cls._functions is None else cls._functions, cast(str, cls._release_name))

    def __init__(self, ptr: Optional[int], context: Any) -> None:
        global _live
        if not ptr:
            raise ValueError("cagekit: NULL %s" % self._kind)
        self._ptr = ptr
        self._context = context  # the Python Context: keeps its callbacks alive while C may call them
        with _live_lock:
            _live += 1

    @property
    def context(self) -> _context_module.Context:
        """The Context whose callbacks and error messages this object uses."""
        return self._context

    @property
    def closed(self) -> bool:
        return self._ptr is None

    @property
    def _handle(self) -> int:
        if self._ptr is None:
            raise ValueError("cagekit: this %s is closed" % self._kind)
        return self._ptr

    def close(self) -> None:
        """Releases the handle now (idempotent). Objects made from it stay valid."""
        global _live
        ptr, self._ptr = getattr(self, "_ptr", None), None
        if ptr is not None:
            self._release()(ptr)
            with _live_lock:
                _live -= 1

    def __enter__(self: _H) -> _H:
        return self

    def __exit__(self, *exc: object) -> Literal[False]:
        self.close()
        return False

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:  # interpreter shutdown: modules may already be gone
            pass

    def __repr__(self) -> str:
        state = "closed" if self._ptr is None else "0x%x" % self._ptr
        return "<cagekit.%s %s>" % (type(self).__name__, state)
