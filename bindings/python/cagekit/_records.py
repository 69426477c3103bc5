# SPDX-License-Identifier: GPL-3.0-or-later
"""Plain Python records made from the C report structs (no ctypes objects leak out)."""
from __future__ import annotations

import ctypes
from typing import TYPE_CHECKING, Any, Dict


class Record:
    """Attributes named as the C struct's fields (struct_size left out); arrays become tuples."""

    def __init__(self, _name: str = "Record", **fields: Any) -> None:
        self.__dict__["_name"] = _name
        self.__dict__.update(fields)

    def __setattr__(self, name: str, value: Any) -> None:
        self.__dict__[name] = value

    if TYPE_CHECKING:  # the fields, for type checkers (at run time they are plain attributes)
        def __getattr__(self, name: str) -> Any: ...

    def as_dict(self) -> Dict[str, Any]:
        return {k: v for k, v in self.__dict__.items() if k != "_name"}

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Record) and self.as_dict() == other.as_dict()

    def __repr__(self) -> str:
        return "%s(%s)" % (self._name, ", ".join("%s=%r" % kv for kv in self.as_dict().items()))


def _value(v):
    if isinstance(v, ctypes.Array):
        return tuple(_value(x) for x in v)
    if isinstance(v, ctypes.Structure):
        return from_struct(v)
    if isinstance(v, bytes):
        return v.decode("utf-8", "replace")
    return v


def from_struct(struct, name=None, skip=("struct_size",)):
    fields = {}
    for field in struct._fields_:
        if field[0] in skip:
            continue
        fields[field[0]] = _value(getattr(struct, field[0]))
    return Record(name or type(struct).__name__, **fields)


def enum_value(cls, value):
    """A member of the IntEnum `cls` from a member, an int or a name ('local-frame', 'EXACT', ...)."""
    if isinstance(value, str):
        try:
            return cls[value.upper().replace("-", "_")]
        except KeyError:
            raise ValueError("cagekit: %r is not one of %s" % (value, ", ".join(m.name.lower() for m in cls))) \
                from None
    return cls(int(value))
