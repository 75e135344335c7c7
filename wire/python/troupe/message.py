"""Messages: reading a verified frame and building new ones with the code
flatc --python generated from wire/schemas/ (the troupe.wire modules)."""

from __future__ import annotations

import time
from typing import NamedTuple

import flatbuffers

from troupe.wire import Message as _msg
from troupe.wire.Address import Address as _AddressStruct
from troupe.wire.Body import Body
from troupe.wire.Header import CreateHeader
from troupe.wire.Kind import Kind

from .address import Address
from .verify import Verifier, VerifyError

#: The protocol version this package speaks (Hello.protocol_version).
PROTOCOL_VERSION = 1

#: Kind names as the C++ side prints them.
KIND_NAMES = ["invalid", "data", "command", "request", "ack", "nack", "hello", "devlist", "open", "close", "pull",
              "timesync", "error"]

#: Body type codes by generated class name ("RangerScan" -> 12).
BODY_CODES = {k: v for k, v in vars(Body).items() if not k.startswith("_") and k != "NONE"}


def kind_name(kind: int) -> str:
    return KIND_NAMES[kind] if 0 <= kind < len(KIND_NAMES) else "unknown"


def now_us() -> int:
    """This process's monotonic clock, us (what headers carry)."""
    return time.monotonic_ns() // 1000


class Header(NamedTuple):
    """The 20-byte header of every message."""
    addr: Address
    kind: int
    subtype: int
    #: Data: the device's sample counter. Requests and replies: chosen by the client.
    seq: int
    #: The sender's clock, us.
    time_us: int


class Message:
    """A frame that passed the verifier: its header decoded, its body
    readable through the generated classes (body_as)."""

    __slots__ = ("frame", "header", "body_type", "_root")

    def __init__(self, frame: bytes, root: int):
        self.frame = frame
        self._root = root
        m = _msg.Message()
        m.Init(frame, root)
        h = m.Header()
        if h is None:
            raise VerifyError("Message.header: missing", root)
        a = h.Addr(_AddressStruct())
        self.header = Header(Address(a.Robot(), a.Iface(), a.Index()), h.Kind(), h.Subtype(), h.Seq(),
                             (h.TimeUsHi() << 32) | h.TimeUsLo())
        self.body_type = m.BodyType()

    def body_as(self, cls):
        """The body as an instance of the generated class `cls` (e.g. RangerScan),
        or None when the body is absent or of another type."""
        if self.body_type == 0 or BODY_CODES.get(cls.__name__) != self.body_type:
            return None
        m = _msg.Message()
        m.Init(self.frame, self._root)
        table = m.Body()
        if table is None:
            return None
        obj = cls()
        obj.Init(self.frame, table.Pos)
        return obj

    def __repr__(self) -> str:
        h = self.header
        body = next((k for k, v in BODY_CODES.items() if v == self.body_type), "none")
        return f"<Message {kind_name(h.kind)} {h.addr} subtype={h.subtype} seq={h.seq} t={h.time_us}us body={body}>"


def decode(frame: bytes, verifier: Verifier) -> Message:
    """Verifies a frame and returns its message; raises VerifyError when the
    frame is malformed."""
    return Message(frame, verifier.verify(frame))


class MessageWriter:
    """Builds frames: start() gives a builder for the body, finish() adds the
    header and returns the frame, prefix included."""

    def __init__(self):
        self._builder: flatbuffers.Builder | None = None

    def start(self) -> flatbuffers.Builder:
        self._builder = flatbuffers.Builder(256)
        return self._builder

    def finish(self, addr: Address, kind: int, subtype: int = 0, seq: int = 0, time_us: int | None = None,
               body_type: int = 0, body: int = 0) -> bytes:
        """The frame of a message whose body (if any) was built since start()."""
        b = self._builder if self._builder is not None and body else flatbuffers.Builder(64)
        self._builder = None
        t = now_us() if time_us is None else time_us
        _msg.MessageStart(b)
        # The union type first, as the C++ writer does: no padding before the header.
        _msg.MessageAddBodyType(b, body_type)
        _msg.MessageAddHeader(b, CreateHeader(b, addr.robot, addr.iface, addr.index, kind, subtype,
                                              seq & 0xFFFFFFFF, t & 0xFFFFFFFF, (t >> 32) & 0xFFFFFFFF))
        if body:
            _msg.MessageAddBody(b, body)
        b.FinishSizePrefixed(_msg.MessageEnd(b))
        return bytes(b.Output())


__all__ = ["Address", "Body", "Header", "Kind", "Message", "MessageWriter", "PROTOCOL_VERSION", "decode",
           "kind_name", "now_us"]
