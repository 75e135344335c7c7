"""Proxies: one object per remote device, holding its latest data and
offering its commands and requests as methods (Player's client proxies, the
C++ wire/client/proxy.h). A proxy opens its device when constructed; the
client re-opens it after a reconnect, so a proxy stays usable for the
client's whole life. Dropping the last reference to a proxy unhooks it."""

from __future__ import annotations

import math
import struct
from typing import NamedTuple

from troupe.wire.Access import Access
from troupe.wire.Body import Body
from troupe.wire.Delivery import Delivery

from .address import Address
from .client import Client, Reply
from .message import Message
from .schema import message_schema


class Pose2(NamedTuple):
    """A pose or velocity in the plane: m, m, rad (or per second)."""
    x: float = 0.0
    y: float = 0.0
    a: float = 0.0


class Vec3(NamedTuple):
    """A vector in space: m (or as the field says)."""
    x: float = 0.0
    y: float = 0.0
    z: float = 0.0


class Pose3(NamedTuple):
    """A pose in space: m, m, m, rad, rad, rad."""
    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    roll: float = 0.0
    pitch: float = 0.0
    yaw: float = 0.0


def finite(**values: float) -> None:
    """Raises ValueError naming the first value that is NaN or infinite: no
    field of the protocol takes one (wire/README.md, "Valid values"), and a
    node would answer it with Nack BadValue. Ranges beyond that are the
    node's to check."""
    for name, v in values.items():
        if not math.isfinite(v):
            raise ValueError(f"{name} is {v}: it must be a finite number")


def pose2(p) -> Pose2:
    """A generated Pose2d reader as a Pose2 (zeros for None)."""
    return Pose2(p.X(), p.Y(), p.A()) if p is not None else Pose2()


def vec3(v) -> Vec3 | None:
    return Vec3(v.X(), v.Y(), v.Z()) if v is not None else None


def pose3(p) -> Pose3:
    return Pose3(p.X(), p.Y(), p.Z(), p.Roll(), p.Pitch(), p.Yaw()) if p is not None else Pose3()


def scalar_vector(obj, table: str, field_name: str, fmt: str) -> tuple:
    """A vector of scalars of a generated table object, read in one go (the
    generated per-element accessors cost a lookup each; numpy is optional
    and absent here). `fmt` is a struct code: "H" for uint16, "B" for ubyte."""
    tab = obj._tab
    o = tab.Offset(message_schema().field_offset(table, field_name))
    if not o:
        return ()
    n = tab.VectorLen(o)
    return struct.unpack_from(f"<{n}{fmt}", tab.Bytes, tab.Vector(o))


class Proxy:
    """Base of every proxy: the device's address and the bookkeeping of its samples."""

    def __init__(self, client: Client, addr: Address):
        self.client = client
        self.address = addr
        #: Whether the Open was acknowledged (False: see client.error).
        self.is_open = False
        #: Sender timestamp of the latest data, us (node clock); 0 before any.
        self.time_us = 0
        #: The device's sample counter at the latest data.
        self.seq = 0
        #: Samples received so far.
        self.samples = 0
        self._fresh = False

    def fresh(self) -> bool:
        """True once per new sample: reading it clears it."""
        f, self._fresh = self._fresh, False
        return f

    def detach(self) -> None:
        """Stops updating this proxy (the device stays open on the node)."""
        self.client._remove_proxy(self)

    def _attach(self, access: int = Access.All, delivery: int = Delivery.Push, compression: int = 0) -> None:
        """Registers with the client and opens the device. Subclasses call it
        last in __init__: data may arrive during the Open and must find the
        proxy fully built."""
        self.client._add_proxy(self)
        self.is_open = self.client.open(self.address, access, delivery, compression=compression)

    def _receive(self, msg: Message) -> None:
        h = msg.header
        self.time_us, self.seq = h.time_us, h.seq
        self.samples += 1
        self._fresh = True
        self._update(msg)

    def _update(self, msg: Message) -> None:
        """Decodes a Data message for this device (already verified)."""

    def _request(self, subtype: int, body_type: int = Body.NONE, body: int = 0, timeout: float = 2.0) -> Reply:
        return self.client.request(self.address, subtype, body_type, body, timeout)

    def _command(self, subtype: int, body_type: int, body: int) -> bool:
        return self.client.command(self.address, subtype, body_type, body)
