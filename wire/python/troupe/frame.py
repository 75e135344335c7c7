"""Framing: a frame is a u32 little-endian length, then that many bytes of
FlatBuffer (FlatBuffers' size-prefixed form). FrameReader cuts a byte stream
into frames the way wire/frame.h does in C++."""

from __future__ import annotations

import struct

#: Bytes of the length prefix.
PREFIX_BYTES = 4

_U32 = struct.Struct("<I")


def read_prefix(data, at: int = 0) -> int:
    """The length a prefix announces, bytes after the prefix."""
    return _U32.unpack_from(data, at)[0]


class FrameReader:
    """Cuts a byte stream into frames.

    Copes with frames split across reads and several frames in one read. A
    length prefix announcing more than `max_frame_bytes` (prefix included)
    stops the reader before any buffer grows for it: too_large turns true
    and the stream cannot be resynchronised. Memory held is at most one
    frame plus one read.
    """

    def __init__(self, max_frame_bytes: int = 1 << 20):
        self.max_frame_bytes = max_frame_bytes
        self._buf = bytearray()
        self._head = 0
        #: True once the stream announced a frame over the limit.
        self.too_large = False
        #: The oversized frame's announced length, bytes after the prefix.
        self.announced_bytes = 0

    def feed(self, data: bytes) -> None:
        """Appends bytes read from the stream."""
        if self.too_large:
            return
        if self._head and self._head == len(self._buf):
            self._buf.clear()
            self._head = 0
        self._buf += data

    def next(self) -> bytes | None:
        """The next whole frame (prefix included), or None when more bytes are
        needed or the stream is broken (see too_large)."""
        if self.too_large:
            return None
        avail = len(self._buf) - self._head
        if avail < PREFIX_BYTES:
            return None
        size = read_prefix(self._buf, self._head)
        if size + PREFIX_BYTES > self.max_frame_bytes:
            self.too_large = True
            self.announced_bytes = size
            self._buf = bytearray()
            self._head = 0
            return None
        if avail < PREFIX_BYTES + size:
            return None
        start = self._head
        self._head += PREFIX_BYTES + size
        frame = bytes(self._buf[start:self._head])
        # Drop consumed bytes once they are the larger part, so a long stream
        # of small frames does not keep everything it ever read.
        if self._head > 65536 and self._head * 2 > len(self._buf):
            del self._buf[:self._head]
            self._head = 0
        return frame

    def pending_bytes(self) -> int:
        """Bytes held that do not yet form a whole frame (a truncated frame
        when the stream ends)."""
        return len(self._buf) - self._head
