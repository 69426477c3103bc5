# SPDX-License-Identifier: GPL-3.0-or-later
"""Context: the owner of the log and progress callbacks of the objects made with it.

    def progress(stage, fraction):      # stage: "reading", "subdivide", "fit", ...
        print(stage, fraction)
        return not user_pressed_escape   # False cancels: the call raises CancelledError

    with cagekit.Context(progress=progress, log=print) as ctx:
        mesh = cagekit.Mesh.read("scan.obj", context=ctx)

Callbacks run on the thread that made the call, with the GIL held (ctypes takes it back for
them; the GIL is released while the C code runs). A Python exception raised inside a callback
never crosses into C: it is stored, the operation is cancelled (progress) and the exception is
raised again, unchanged, when the C call returns; the SDK stays usable. This includes
KeyboardInterrupt: with a progress callable set, Ctrl-C cancels a long call and raises
KeyboardInterrupt when it returns. Progress callables may return None (continue), a true value
(continue) or a false value other than None (cancel).
"""
from __future__ import annotations

import ctypes
import enum
import threading
import weakref
from typing import Any, Callable, Optional, Union

from . import _errors, _lib
from ._handle import Handle


class LogLevel(enum.IntEnum):
    DEBUG = 0
    INFO = 1
    WARNING = 2
    ERROR = 3


# log(level, message); progress(stage, fraction) -> None / bool (see the module doc).
LogCallable = Callable[[LogLevel, str], Any]
ProgressCallable = Callable[[str, float], Optional[bool]]

_DESC = _lib.ContextDesc.defaults()  # CAGEKIT_CONTEXT_DESC_INIT, written once (in _lib.ContextDesc)


def _progress_trampoline(ref):
    def progress(user_data, stage, fraction):
        # The whole body is inside try: even a KeyboardInterrupt delivered here (Ctrl-C during a
        # long call) is stored, cancels the operation and is raised when the call returns.
        local = None
        try:
            ctx = ref()
            if ctx is None:
                return 1
            local = ctx._local
            if ctx._progress is None:
                return 1
            if getattr(local, "pending", None) is not None:
                return 0  # an earlier callback of this call failed: keep cancelling
            result = ctx._progress(stage.decode("utf-8", "replace") if stage else "", fraction)
            return 0 if (result is not None and not result) else 1
        except BaseException as e:  # never into C; re-raised after the call returns
            if local is not None and getattr(local, "pending", None) is None:
                local.pending = e
            return 0
    return _lib.PROGRESS_FN(progress)


def _log_trampoline(ref):
    def log(user_data, level, message):
        local = None
        try:
            ctx = ref()
            if ctx is None or ctx._log is None:
                return
            local = ctx._local
            try:
                level = LogLevel(level)
            except ValueError:
                pass
            ctx._log(level, message.decode("utf-8", "replace") if message else "")
        except BaseException as e:  # stored; raised when the call returns (a log cannot cancel)
            if local is not None and getattr(local, "pending", None) is None:
                local.pending = e
    return _lib.LOG_FN(log)


class Context(Handle):
    """A CageKit context.

    log: callable(level: LogLevel, message: str) or None; log_level: the lowest level passed.
    progress: callable(stage: str, fraction: float) -> bool/None, or None (see module doc);
    it may be replaced any time through the `progress` attribute.
    memory_budget_bytes: per-call memory budget (0 = unlimited): calls that would need more
    fail with OutOfMemoryError before allocating.
    """

    _release_name = "cagekit_context_release"
    _kind = "context"

    def __init__(self, log: Optional[LogCallable] = None,
                 log_level: Union[LogLevel, int] = LogLevel(_DESC["log_level"]),
                 progress: Optional[ProgressCallable] = None,
                 memory_budget_bytes: int = _DESC["memory_budget_bytes"]) -> None:
        self._local = threading.local()
        self._log = log
        self._progress = progress
        ref = weakref.ref(self)
        # The ctypes callback objects live as long as this Python object, which every object made
        # with the context references, so C never calls a freed trampoline.
        self._progress_fn = _progress_trampoline(ref)
        self._log_fn = _log_trampoline(ref) if log is not None else _lib.LOG_FN()  # type: ignore[call-overload]  # NULL
        desc = _lib.ContextDesc.new(log=self._log_fn, log_level=int(log_level), progress=self._progress_fn,
                                    memory_budget_bytes=int(memory_budget_bytes))
        out = ctypes.c_void_p()
        status = _lib.lib.cagekit_context_create(ctypes.byref(desc), ctypes.byref(out))
        _errors.check(status, None)
        self._raw = out.value  # for error messages, also after close() while objects still use it
        super().__init__(out.value, None)

    @property
    def context(self) -> Context:
        return self

    @property
    def progress(self) -> Optional[ProgressCallable]:
        return self._progress

    @progress.setter
    def progress(self, fn: Optional[ProgressCallable]) -> None:
        """Replaces the progress callable (None: none). Takes effect at the next callback."""
        self._progress = fn

    @property
    def log(self) -> Optional[LogCallable]:
        return self._log

    def cancel(self) -> None:
        """Cancels every running and later long operation of this context (any thread) until
        reset_cancel()."""
        _lib.lib.cagekit_context_cancel(self._handle)

    def reset_cancel(self) -> None:
        _lib.lib.cagekit_context_reset_cancel(self._handle)

    def last_error_message(self) -> str:
        """The message of the last failed call of this thread with objects of this context."""
        return _errors.last_message(self._raw)

    def _call(self, fn: Any, *args: Any, outs: Any = ()) -> int:
        """Calls a C function of this context's objects; raises the stored callback exception or
        the status's CageKitError. outs: (c_void_p, release function, or its name in _lib.lib)
        outputs to release when an exception is raised although the call made them."""
        local = self._local
        local.pending = None
        status = fn(*args)
        pending, local.pending = local.pending, None
        if pending is not None:
            for out, release in outs:
                if out.value:
                    (getattr(_lib.lib, release) if isinstance(release, str) else release)(out.value)
                    out.value = None
            raise pending
        if status < 0:
            raise _errors.error_for(status, self._raw)
        return status


_default: Optional[Context] = None
_default_lock = threading.Lock()


def default_context() -> Context:
    """The context used when none is given: no callbacks, no memory budget."""
    global _default
    with _default_lock:
        if _default is None:
            _default = Context()
        return _default


def resolve(context: Optional[Context]) -> Context:
    return default_context() if context is None else context
