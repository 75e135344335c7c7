"""Addresses as people write them: devices "[ROBOT/]INTERFACE:INDEX"
(Player's style, e.g. "position2d:0", "r3/ranger:1") and hosts
"HOST[:PORT]" (e.g. "localhost", "10.0.0.7:6670", "[::1]:6665"). The same
rules and messages as wire/address.h."""

from __future__ import annotations

from typing import NamedTuple

from troupe.wire.Interface import Interface

#: Default TCP (and UDP) port of a node or simulator.
DEFAULT_PORT = 6665

#: Interface names by code, from the generated enum: "position2d", "ranger", ...
INTERFACE_NAMES = {v: k.lower() for k, v in vars(Interface).items() if not k.startswith("_")}
_INTERFACE_CODES = {name: code for code, name in INTERFACE_NAMES.items() if code != Interface.None_}


class Address(NamedTuple):
    """A device address: robot number, interface code, instance index."""
    robot: int
    iface: int
    index: int

    @staticmethod
    def of(iface: int, index: int = 0, robot: int = 0) -> "Address":
        return Address(robot, iface, index)

    def __str__(self) -> str:
        return format_address(self)


class DeviceSpec(NamedTuple):
    """A device named by a user; `robot` is a name or number as written, empty for robot 0."""
    robot: str
    iface: int
    index: int


def interface_name(code: int) -> str:
    """"position2d", "ranger", ...; "unknown" for a code this build does not know."""
    return INTERFACE_NAMES.get(code, "unknown") if code != Interface.None_ else "none"


def interface_from_name(name: str) -> int:
    """The code of an interface name, or Interface.None_ when unknown."""
    return _INTERFACE_CODES.get(name, Interface.None_)


def _parse_uint(text: str, maximum: int) -> int | None:
    if not text or not text.isascii() or not text.isdigit():
        return None
    value = int(text)
    return value if value <= maximum else None


def parse_device(text: str) -> DeviceSpec:
    """Parses "[ROBOT/]INTERFACE:INDEX"; raises ValueError saying why it cannot."""
    robot, rest = "", text
    if "/" in rest:
        robot, rest = rest.split("/", 1)
        if not robot:
            raise ValueError(f"empty robot name in '{text}'")
    if ":" not in rest:
        raise ValueError(f"'{text}' is not [ROBOT/]INTERFACE:INDEX (e.g. position2d:0)")
    name, index_text = rest.rsplit(":", 1)
    iface = interface_from_name(name)
    if iface == Interface.None_:
        raise ValueError(f"unknown interface '{name}' in '{text}'")
    index = _parse_uint(index_text, 0xFFFF)
    if index is None:
        raise ValueError(f"bad index in '{text}' (want 0..65535)")
    return DeviceSpec(robot, iface, index)


def robot_number(robot: str) -> int:
    """The robot number when `robot` is empty or all digits; -1 for a name."""
    if not robot:
        return 0
    n = _parse_uint(robot, 0xFFFF)
    return -1 if n is None else n


def format_address(addr: Address, robot_name: str = "") -> str:
    """"position2d:0" for robot 0 without a name, else "NAME/position2d:0" (or "3/position2d:0")."""
    prefix = f"{robot_name}/" if robot_name else (f"{addr.robot}/" if addr.robot else "")
    return f"{prefix}{interface_name(addr.iface)}:{addr.index}"


def parse_host(text: str) -> tuple[str, int]:
    """Parses "HOST[:PORT]" (IPv6 literals in brackets) into (host, port); raises ValueError."""
    host, port = text, ""
    if text.startswith("["):
        close = text.find("]")
        if close < 0:
            raise ValueError(f"missing ']' in '{text}'")
        host, after = text[1:close], text[close + 1:]
        if after:
            if not after.startswith(":"):
                raise ValueError(f"unexpected text after ']' in '{text}'")
            port = after[1:]
            if not port:
                raise ValueError(f"empty port in '{text}'")
    elif ":" in text:
        if text.count(":") > 1:
            raise ValueError(f"IPv6 addresses need brackets: [{text}]")
        host, port = text.split(":")
        if not port:
            raise ValueError(f"empty port in '{text}'")
    if not host:
        raise ValueError("empty host name")
    if not port:
        return host, DEFAULT_PORT
    p = _parse_uint(port, 65535)
    if not p:
        raise ValueError(f"bad port '{port}' (want 1..65535)")
    return host, p
