"""The protocol's shape at run time, for the verifier.

Python's FlatBuffers runtime has no verifier, so this package carries one
(verify.py). It needs to know, for every table, which fields are offsets
(strings, vectors, sub-tables, union bodies) and how big each inline field
is. Rather than a hand-kept copy of the schemas, that comes from the binary
schema (message.bfbs) that flatc writes from the same wire/schemas/*.fbs at
build time: a FlatBuffer of FlatBuffers' own reflection schema, read here
with the runtime's plain Table accessor. The slot numbers below are
reflection.fbs's field ids, which FlatBuffers keeps stable.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

from flatbuffers import encode
from flatbuffers import number_types as N
from flatbuffers.table import Table

# reflection.BaseType
NONE, UTYPE, BOOL, BYTE, UBYTE, SHORT, USHORT, INT, UINT, LONG, ULONG, FLOAT, DOUBLE = range(13)
STRING, VECTOR, OBJ, UNION, ARRAY = range(13, 18)

#: Inline size of each scalar base type, bytes.
SCALAR_BYTES = {UTYPE: 1, BOOL: 1, BYTE: 1, UBYTE: 1, SHORT: 2, USHORT: 2, INT: 4, UINT: 4,
                LONG: 8, ULONG: 8, FLOAT: 4, DOUBLE: 8}

# Field ids in reflection.fbs (the vtable slot is 4 + 2 * id).
_SCHEMA_OBJECTS, _SCHEMA_ENUMS, _SCHEMA_ROOT = 0, 1, 4
_OBJECT_NAME, _OBJECT_FIELDS, _OBJECT_IS_STRUCT, _OBJECT_MINALIGN, _OBJECT_BYTESIZE = 0, 1, 2, 3, 4
_FIELD_NAME, _FIELD_TYPE, _FIELD_ID, _FIELD_OFFSET, _FIELD_DEPRECATED, _FIELD_REQUIRED = 0, 1, 2, 3, 6, 7
_TYPE_BASE, _TYPE_ELEMENT, _TYPE_INDEX = 0, 1, 2
_ENUM_NAME, _ENUM_VALUES, _ENUM_IS_UNION = 0, 1, 2
_VALUE_VALUE, _VALUE_UNION_TYPE = 1, 3


@dataclass
class FieldShape:
    """One field of a table or struct as the verifier needs it."""
    name: str
    id: int
    #: Tables: the field's slot in the vtable, bytes. Structs: its offset in the struct, bytes.
    offset: int
    base: int
    element: int
    #: Object index (OBJ, or VECTOR of OBJ) or enum index (UNION, UTYPE), else -1.
    index: int
    required: bool


@dataclass
class ObjectShape:
    """A table or a struct."""
    name: str
    is_struct: bool
    #: Structs: size in bytes and alignment, bytes.
    bytesize: int
    minalign: int
    fields: list[FieldShape] = field(default_factory=list)


@dataclass
class Schema:
    objects: list[ObjectShape]
    #: Union enums by enum index: union type value -> object index.
    unions: dict[int, dict[int, int]]
    root: int

    def index_of(self, name: str) -> int:
        for i, o in enumerate(self.objects):
            if o.name == name:
                return i
        raise KeyError(name)

    def field_offset(self, table: str, field_name: str) -> int:
        """A table field's vtable slot, bytes ("troupe.wire.RangerScan", "ranges" -> 4)."""
        for f in self.objects[self.index_of(table)].fields:
            if f.name == field_name:
                return f.offset
        raise KeyError(f"{table}.{field_name}")


def _slot(t: Table, field_id: int) -> int:
    return t.Offset(4 + 2 * field_id)


def _scalar(t: Table, field_id: int, flags, default):
    return t.GetSlot(4 + 2 * field_id, default, flags)


def _string(t: Table, field_id: int) -> str:
    o = _slot(t, field_id)
    return t.String(o + t.Pos).decode("utf-8") if o else ""


def _table(t: Table, field_id: int) -> Table | None:
    o = _slot(t, field_id)
    return Table(t.Bytes, t.Indirect(o + t.Pos)) if o else None


def _tables(t: Table, field_id: int) -> list[Table]:
    o = _slot(t, field_id)
    if not o:
        return []
    start, n = t.Vector(o), t.VectorLen(o)
    return [Table(t.Bytes, t.Indirect(start + 4 * i)) for i in range(n)]


def parse_bfbs(data: bytes) -> Schema:
    """Reads a binary schema (flatc --schema -b) into the verifier's shapes."""
    buf = bytearray(data)
    if len(buf) < 8 or buf[4:8] != b"BFBS":
        raise ValueError("not a FlatBuffers binary schema (no BFBS identifier)")
    root = Table(buf, encode.Get(N.UOffsetTFlags.packer_type, buf, 0))
    objects = []
    for o in _tables(root, _SCHEMA_OBJECTS):
        shape = ObjectShape(_string(o, _OBJECT_NAME), _scalar(o, _OBJECT_IS_STRUCT, N.BoolFlags, False),
                            _scalar(o, _OBJECT_BYTESIZE, N.Int32Flags, 0),
                            _scalar(o, _OBJECT_MINALIGN, N.Int32Flags, 1))
        for f in _tables(o, _OBJECT_FIELDS):
            if _scalar(f, _FIELD_DEPRECATED, N.BoolFlags, False):
                continue
            ty = _table(f, _FIELD_TYPE)
            shape.fields.append(FieldShape(
                _string(f, _FIELD_NAME), _scalar(f, _FIELD_ID, N.Uint16Flags, 0),
                _scalar(f, _FIELD_OFFSET, N.Uint16Flags, 0), _scalar(ty, _TYPE_BASE, N.Int8Flags, NONE),
                _scalar(ty, _TYPE_ELEMENT, N.Int8Flags, NONE), _scalar(ty, _TYPE_INDEX, N.Int32Flags, -1),
                _scalar(f, _FIELD_REQUIRED, N.BoolFlags, False)))
        shape.fields.sort(key=lambda s: s.id)
        objects.append(shape)
    unions = {}
    for i, e in enumerate(_tables(root, _SCHEMA_ENUMS)):
        if not _scalar(e, _ENUM_IS_UNION, N.BoolFlags, False):
            continue
        members = {}
        for v in _tables(e, _ENUM_VALUES):
            ut = _table(v, _VALUE_UNION_TYPE)
            if ut is not None and _scalar(ut, _TYPE_BASE, N.Int8Flags, NONE) == OBJ:
                members[_scalar(v, _VALUE_VALUE, N.Int64Flags, 0)] = _scalar(ut, _TYPE_INDEX, N.Int32Flags, -1)
        unions[i] = members
    root_object = _table(root, _SCHEMA_ROOT)
    if root_object is None:
        raise ValueError("binary schema has no root table")
    names = [o.name for o in objects]
    return Schema(objects, unions, names.index(_string(root_object, _OBJECT_NAME)))


_message_schema: Schema | None = None


def message_schema() -> Schema:
    """The wire protocol's schema, from the message.bfbs installed beside this file."""
    global _message_schema
    if _message_schema is None:
        path = os.path.join(os.path.dirname(__file__), "message.bfbs")
        with open(path, "rb") as f:
            _message_schema = parse_bfbs(f.read())
    return _message_schema
