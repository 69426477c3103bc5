# SPDX-License-Identifier: GPL-3.0-or-later
"""Plain Python records made from the C report structs (no ctypes objects leak out)."""
import ctypes


class Record:
    """Attributes named as the C struct's fields (struct_size left out); arrays become tuples."""

    def __init__(self, _name="Record", **fields):
        self.__dict__["_name"] = _name
        self.__dict__.update(fields)

    def __setattr__(self, name, value):
        self.__dict__[name] = value

    def as_dict(self):
        return {k: v for k, v in self.__dict__.items() if k != "_name"}

    def __eq__(self, other):
        return isinstance(other, Record) and self.as_dict() == other.as_dict()

    def __repr__(self):
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
