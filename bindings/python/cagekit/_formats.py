# SPDX-License-Identifier: GPL-3.0-or-later
"""File formats and the write options shared by meshes and cages."""
from __future__ import annotations

import ctypes
import enum
import os
from typing import Any, Literal, Optional, Tuple, Union, overload

from . import _lib
from ._records import Record, from_struct
from ._typing import StrPath


class FileFormat(enum.IntEnum):
    AUTO = 0   # by extension (files) or by sniffing (memory)
    OBJ = 1    # keeps cage tags (OpenSubdiv `t crease/corner/hole`)
    PLY = 2
    OFF = 3
    DRACO = 4  # keeps cage tags
    STL = 5    # read only (binary or ascii); writing raises UNSUPPORTED_FORMAT


# A format argument: a FileFormat, its int, a name ('obj', '.ply', 'draco', ...) or None (AUTO).
FormatLike = Union[FileFormat, int, str, None]

_NAMES = {"auto": FileFormat.AUTO, "obj": FileFormat.OBJ, "ply": FileFormat.PLY, "off": FileFormat.OFF,
          "drc": FileFormat.DRACO, "draco": FileFormat.DRACO, "stl": FileFormat.STL}


def file_format(value: FormatLike) -> FileFormat:
    """FileFormat from a FileFormat, an int or a name ('obj', 'ply', 'off', 'drc'/'draco', 'stl', 'auto')."""
    if value is None:
        return FileFormat.AUTO
    if isinstance(value, str):
        try:
            return _NAMES[value.lower().lstrip(".")]
        except KeyError:
            raise ValueError("cagekit: unknown file format %r (obj, ply, off, drc, stl, auto)" % value) from None
    return FileFormat(int(value))


def path_bytes(path: Any) -> bytes:
    return os.fsencode(os.fspath(path))


def write_options(format, ply_binary, draco_position_bits, draco_speed):
    return _lib.WriteOptions.new(format=int(file_format(format)), ply_binary=1 if ply_binary else 0,
                                 draco_position_bits=int(draco_position_bits), draco_speed=int(draco_speed))


def write_file(obj, fn_name, path, format, ply_binary, draco_position_bits, draco_speed):
    options = write_options(format, ply_binary, draco_position_bits, draco_speed)
    report = _lib.WriteReport.new()
    obj._context._call(getattr(_lib.lib, fn_name), obj._handle, path_bytes(path), ctypes.byref(options),
                       ctypes.byref(report))
    return from_struct(report, "WriteReport")


def write_memory(obj, fn_name, format, ply_binary, draco_position_bits, draco_speed, with_report=False):
    if file_format(format) == FileFormat.AUTO:
        raise ValueError("cagekit: to_bytes needs a format (obj, ply, off, drc)")
    options = write_options(format, ply_binary, draco_position_bits, draco_speed)
    report = _lib.WriteReport.new()
    blob = ctypes.c_void_p()
    obj._context._call(getattr(_lib.lib, fn_name), obj._handle, ctypes.byref(options), ctypes.byref(blob),
                       ctypes.byref(report), outs=[(blob, "cagekit_blob_release")])
    data = blob_bytes(blob)
    return (data, from_struct(report, "WriteReport")) if with_report else data


_WRITE = _lib.WriteOptions.defaults()  # CAGEKIT_WRITE_OPTIONS_INIT, written once (in _lib)


class Writable:
    """write() and to_bytes() of a handle class (Mesh, Cage): its C functions are named by
    `_write_functions` (write_file, write_memory); the handle gives `_context` and `_handle`."""

    _write_functions: Tuple[str, str]

    def write(self, path: StrPath, format: FormatLike = "auto", *, ply_binary: bool = bool(_WRITE["ply_binary"]),
              draco_position_bits: int = _WRITE["draco_position_bits"],
              draco_speed: int = _WRITE["draco_speed"]) -> Record:
        """Writes atomically (format 'auto': by the extension); returns a record with `bytes` and
        `max_position_error`. A cage's tags are kept by OBJ and Draco; PLY and OFF drop them with a
        logged warning."""
        return write_file(self, self._write_functions[0], path, format, ply_binary, draco_position_bits, draco_speed)

    @overload
    def to_bytes(self, format: FormatLike, *, ply_binary: bool = ..., draco_position_bits: int = ...,
                 draco_speed: int = ..., report: Literal[False] = ...) -> bytes: ...

    @overload
    def to_bytes(self, format: FormatLike, *, ply_binary: bool = ..., draco_position_bits: int = ...,
                 draco_speed: int = ..., report: Literal[True]) -> Tuple[bytes, Record]: ...

    def to_bytes(self, format: FormatLike, *, ply_binary: bool = bool(_WRITE["ply_binary"]),
                 draco_position_bits: int = _WRITE["draco_position_bits"], draco_speed: int = _WRITE["draco_speed"],
                 report: bool = False) -> Union[bytes, Tuple[bytes, Record]]:
        """The file's bytes in `format` ('obj', 'ply', 'off', 'drc'); with report=True also the
        write report."""
        return write_memory(self, self._write_functions[1], format, ply_binary, draco_position_bits, draco_speed,
                            report)


def blob_bytes(blob):
    """The bytes of a blob handle (c_void_p), which is released."""
    try:
        size = _lib.lib.cagekit_blob_size(blob)
        return ctypes.string_at(_lib.lib.cagekit_blob_data(blob), size) if size else b""
    finally:
        _lib.lib.cagekit_blob_release(blob)


def input_bytes(data):
    """(buffer object kept alive, address, size) for read-from-memory calls; any bytes-like object."""
    view = memoryview(data).cast("B") if not isinstance(data, bytes) else data
    if isinstance(view, bytes):
        return view, ctypes.cast(ctypes.c_char_p(view), ctypes.c_void_p), len(view)
    if view.readonly:
        copy = bytes(view)
        return copy, ctypes.cast(ctypes.c_char_p(copy), ctypes.c_void_p), len(copy)
    buffer = (ctypes.c_char * len(view)).from_buffer(view)
    return (view, buffer), ctypes.cast(buffer, ctypes.c_void_p), len(view)
