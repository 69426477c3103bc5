# SPDX-License-Identifier: GPL-3.0-or-later
"""Exceptions: one CageKitError subclass per cagekit_status, carrying the SDK's message.

The message is cagekit_last_error_message(context) read on the calling thread right after the
failed call (the C library keeps the last error per thread and per context). Some classes also
derive from the matching built-in exception (InvalidArgumentError is a ValueError,
OutOfMemoryError a MemoryError, FileIOError an OSError), so generic handlers catch them too.
"""
from __future__ import annotations

from typing import Any, Optional

from . import _lib


class CageKitError(Exception):
    """A failed CageKit call. `status` is the cagekit_status (negative int), `message` the
    SDK's message (may be empty), `status_name` the status's English name."""

    status: Optional[int] = None

    def __init__(self, message: str = "", status: Optional[int] = None) -> None:
        if status is not None:
            self.status = status
        self.message = message
        self.status_name = status_name(self.status) if self.status is not None else "error"
        super().__init__(message or self.status_name)

    def __str__(self) -> str:
        return self.message or self.status_name


class InvalidArgumentError(CageKitError, ValueError):
    status = -1


class InvalidHandleError(CageKitError):
    status = -2


class OutOfMemoryError(CageKitError, MemoryError):
    status = -3


class SizeInsufficientError(CageKitError):
    status = -4


class FileIOError(CageKitError, OSError):
    status = -5


class ParseError(CageKitError):
    status = -6


class UnsupportedFormatError(CageKitError):
    status = -7


class InvalidMeshError(CageKitError):
    status = -8
    report: Any  # Mesh.validate(check=True) sets it: the validation record


class LimitExceededError(CageKitError):
    status = -9


class CancelledError(CageKitError):
    status = -10


class InternalError(CageKitError):
    status = -11


class VersionMismatchError(CageKitError):
    status = -12


class QualityError(CageKitError):
    """A result was computed but misses its quality bounds; the message names the figure."""
    status = -13


class UnsupportedFeatureError(CageKitError):
    """The environment or the object lacks a feature the call needs (a GL context too old, ...)."""
    status = -14


class InvalidOperationError(CageKitError):
    """The call is not allowed in the object's current state (an update before a first deform, ...)."""
    status = -15


ERROR_CLASSES = {cls.status: cls for cls in (
    InvalidArgumentError, InvalidHandleError, OutOfMemoryError, SizeInsufficientError, FileIOError, ParseError,
    UnsupportedFormatError, InvalidMeshError, LimitExceededError, CancelledError, InternalError,
    VersionMismatchError, QualityError, UnsupportedFeatureError, InvalidOperationError)}


def status_name(status: int) -> str:
    name = _lib.lib.cagekit_status_string(status)
    return name.decode("utf-8", "replace") if name else "status %d" % status


def last_message(context_ptr: Optional[int]) -> str:
    """cagekit_last_error_message(context) of the calling thread, as str."""
    text = _lib.lib.cagekit_last_error_message(context_ptr)
    return text.decode("utf-8", "replace") if text else ""


def error_for(status: int, context_ptr: Optional[int]) -> CageKitError:
    """The exception for a failed status, with the thread's last message of that context."""
    cls = ERROR_CLASSES.get(status, CageKitError)
    return cls(last_message(context_ptr), status)


def check(status: int, context_ptr: Optional[int]) -> int:
    """Raises the matching CageKitError when status < 0; returns status otherwise."""
    if status < 0:
        raise error_for(status, context_ptr)
    return status
