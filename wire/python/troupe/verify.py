"""A FlatBuffers verifier for wire frames, because Python's runtime has none.

The Python FlatBuffers runtime reads whatever offsets a buffer holds: on a
malformed frame it raises from deep inside an accessor, or worse, quietly
returns bytes from somewhere else (negative positions index from the end,
string slices are cut short). So every inbound frame goes through verify()
before any generated accessor touches it, with the same rules and limits as
the C++ side (flatbuffers::Verifier via wire/frame.h):

- the length prefix matches the frame;
- every table's vtable, and every field the vtable points to, lies inside
  the frame and inside its table, aligned;
- every offset is non-zero and points inside the frame; strings are
  NUL-terminated, vectors fit whole;
- union bodies are verified as the table their type names (an unknown type,
  from a newer peer, is left unread, as C++ does);
- required fields are present; nesting depth and table count are bounded.

What is not checked (neither does the C++ verifier): that enum values are
known and that strings are valid UTF-8; readers decode with replacement.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

from . import schema as S

_U16 = struct.Struct("<H").unpack_from
_U32 = struct.Struct("<I").unpack_from
_I32 = struct.Struct("<i").unpack_from

#: Where frames start their FlatBuffer: after the 4-byte length prefix.
#: Alignment is relative to the frame's first byte: the builder aligns the
#: buffer with its prefix (as C++ verifies it, through the whole frame).
_BASE = 4


@dataclass(frozen=True)
class Limits:
    """Bounds applied to every inbound frame (the C++ wire::Limits)."""
    #: Largest frame accepted, bytes including the 4-byte prefix.
    max_frame_bytes: int = 1 << 20
    #: Deepest nesting of tables the verifier follows.
    max_depth: int = 16
    #: Most tables visited in one frame.
    max_tables: int = 20000


class VerifyError(ValueError):
    """A frame the verifier refused: `offset` is the byte in the frame where it went wrong."""

    def __init__(self, what: str, offset: int):
        super().__init__(f"{what} (byte {offset})")
        self.offset = offset


# How a field is checked, once its slot is known to be present.
_INLINE, _STRING, _TABLE, _VECTOR, _UNION = range(5)


class _Check:
    __slots__ = ("name", "voffset", "kind", "size", "align", "target", "elem", "required", "type_voffset")


def _compile(schema: S.Schema, shape: S.ObjectShape) -> list[_Check]:
    checks = []
    by_id = {f.id: f for f in shape.fields}
    for f in shape.fields:
        c = _Check()
        c.name = f"{shape.name.rsplit('.', 1)[-1]}.{f.name}"
        c.voffset, c.required, c.target, c.elem, c.type_voffset = f.offset, f.required, f.index, None, 0
        c.size = c.align = 4
        if f.base in S.SCALAR_BYTES:
            c.kind, c.size = _INLINE, S.SCALAR_BYTES[f.base]
            c.align = c.size
        elif f.base == S.OBJ and schema.objects[f.index].is_struct:
            struct_shape = schema.objects[f.index]
            c.kind, c.size, c.align = _INLINE, struct_shape.bytesize, struct_shape.minalign
        elif f.base == S.OBJ:
            c.kind = _TABLE
        elif f.base == S.STRING:
            c.kind = _STRING
        elif f.base == S.VECTOR:
            c.kind = _VECTOR
            if f.element in S.SCALAR_BYTES:
                c.elem = ("scalar", S.SCALAR_BYTES[f.element])
            elif f.element == S.OBJ and schema.objects[f.index].is_struct:
                c.elem = ("scalar", schema.objects[f.index].bytesize)
            elif f.element == S.OBJ:
                c.elem = ("table", 4)
            elif f.element == S.STRING:
                c.elem = ("string", 4)
            else:
                raise ValueError(f"{c.name}: vectors of base type {f.element} are not supported")
        elif f.base == S.UNION:
            c.kind = _UNION
            type_field = by_id.get(f.id - 1)
            if type_field is None or type_field.base != S.UTYPE:
                raise ValueError(f"{c.name}: union without its type field")
            c.type_voffset = type_field.offset
        else:
            raise ValueError(f"{c.name}: base type {f.base} is not supported")
        checks.append(c)
    return checks


class Verifier:
    """Checks frames against a schema. One instance serves any number of frames."""

    def __init__(self, schema: S.Schema | None = None, limits: Limits = Limits()):
        self.schema = schema or S.message_schema()
        self.limits = limits
        self._checks = [_compile(self.schema, o) if not o.is_struct else [] for o in self.schema.objects]
        self._tables = 0

    def verify(self, frame: bytes) -> int:
        """Checks a whole frame (prefix included); returns the position of its root table
        or raises VerifyError saying what is wrong and where."""
        n = len(frame)
        if n > self.limits.max_frame_bytes:
            raise VerifyError(f"frame of {n} bytes is over the limit of {self.limits.max_frame_bytes}", 0)
        if n < _BASE + 4:
            raise VerifyError(f"frame of {n} bytes is too short to hold a message", 0)
        if _U32(frame, 0)[0] != n - _BASE:
            raise VerifyError(f"length prefix {_U32(frame, 0)[0]} does not match the {n - _BASE} bytes after it", 0)
        root = self._offset(frame, _BASE, "root offset")
        self._tables = 0
        self._table(frame, root, self.schema.root, 1)
        return root

    def _offset(self, buf, at: int, what: str) -> int:
        off = _U32(buf, at)[0]
        if off == 0 or off >= 1 << 31 or at + off + 4 > len(buf):
            raise VerifyError(f"{what}: offset {off} points outside the frame", at)
        return at + off

    def _table(self, buf, pos: int, obj: int, depth: int) -> None:
        name = self.schema.objects[obj].name.rsplit(".", 1)[-1]
        if depth > self.limits.max_depth:
            raise VerifyError(f"{name}: tables nested deeper than {self.limits.max_depth}", pos)
        self._tables += 1
        if self._tables > self.limits.max_tables:
            raise VerifyError(f"more than {self.limits.max_tables} tables", pos)
        end = len(buf)
        if pos % 4 or pos + 4 > end:
            raise VerifyError(f"{name}: table misaligned or outside the frame", pos)
        vt = pos - _I32(buf, pos)[0]
        if vt < _BASE or vt % 2 or vt + 4 > end:
            raise VerifyError(f"{name}: vtable outside the frame", pos)
        vsize, tsize = _U16(buf, vt)[0], _U16(buf, vt + 2)[0]
        if vsize < 4 or vsize % 2 or vt + vsize > end:
            raise VerifyError(f"{name}: vtable of {vsize} bytes does not fit", vt)
        if tsize < 4 or pos + tsize > end:
            raise VerifyError(f"{name}: table of {tsize} bytes does not fit", pos)
        for c in self._checks[obj]:
            fo = _U16(buf, vt + c.voffset)[0] if c.voffset < vsize else 0
            if fo == 0:
                if c.required:
                    raise VerifyError(f"{c.name}: required field missing", pos)
                continue
            at = pos + fo
            if fo + c.size > tsize or at % c.align:
                raise VerifyError(f"{c.name}: field misaligned or outside its table", at)
            kind = c.kind
            if kind == _INLINE:
                continue
            target = self._offset(buf, at, c.name)
            if kind == _TABLE:
                self._table(buf, target, c.target, depth + 1)
            elif kind == _STRING:
                self._string(buf, target, c.name)
            elif kind == _VECTOR:
                self._vector(buf, target, c, depth)
            else:
                ut = _U16(buf, vt + c.type_voffset)[0] if c.type_voffset < vsize else 0
                member = self.schema.unions[c.target].get(buf[pos + ut] if ut else 0)
                if member is not None:
                    self._table(buf, target, member, depth + 1)

    def _string(self, buf, pos: int, name: str) -> None:
        if pos % 4:
            raise VerifyError(f"{name}: string misaligned", pos)
        n = _U32(buf, pos)[0]
        if pos + 4 + n + 1 > len(buf) or buf[pos + 4 + n] != 0:
            raise VerifyError(f"{name}: string of {n} bytes runs past the frame or lacks its terminator", pos)

    def _vector(self, buf, pos: int, c: _Check, depth: int) -> None:
        what, esize = c.elem
        if pos % 4:
            raise VerifyError(f"{c.name}: vector misaligned", pos)
        n = _U32(buf, pos)[0]
        if pos + 4 + n * esize > len(buf):
            raise VerifyError(f"{c.name}: vector of {n} x {esize} bytes runs past the end of the frame", pos)
        if what == "table":
            for i in range(n):
                self._table(buf, self._offset(buf, pos + 4 + 4 * i, c.name), c.target, depth + 1)
        elif what == "string":
            for i in range(n):
                self._string(buf, self._offset(buf, pos + 4 + 4 * i, c.name), c.name)
