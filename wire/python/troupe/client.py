"""The Python client: a connection to a node or simulator, shaped like the
C++ one (wire/client/client.h). Use it blocking (connect(), request(),
spin_once()) or from your own poll loop (poll_fds(), process(),
next_timeout()). A lost connection is noticed and re-established with
backoff; devices opened before are opened again and proxies keep working.

Single-threaded like the C++ client: call it from one thread. Times are
seconds (float) unless a name says otherwise (time_us, clock_offset_us).
"""

from __future__ import annotations

import errno
import os
import select
import socket
import time
import weakref
from typing import Callable, NamedTuple

from troupe.wire import DeviceList as _dl
from troupe.wire import Error as _err
from troupe.wire import Hello as _hello
from troupe.wire import Open as _open
from troupe.wire import TimeSync as _ts
from troupe.wire.Access import Access
from troupe.wire.Body import Body
from troupe.wire.Delivery import Delivery
from troupe.wire.ErrorCode import ErrorCode
from troupe.wire.Kind import Kind

from .address import DEFAULT_PORT, Address, format_address, parse_device, robot_number
from .frame import FrameReader
from .message import PROTOCOL_VERSION, Message, MessageWriter, decode, now_us
from .verify import Limits, Verifier

_ERROR_NAMES = {v: k for k, v in vars(ErrorCode).items() if not k.startswith("_")}
_IDLE, _CONNECTING, _HANDSHAKE, _CONNECTED = range(4)
_READ_BYTES = 64 * 1024


def _text(raw: bytes | None) -> str:
    return raw.decode("utf-8", "replace") if raw else ""


class Reply:
    """The outcome of a request."""
    ACK, NACK, TIMEOUT, DISCONNECTED = "ack", "nack", "timeout", "disconnected"

    def __init__(self, status: str = TIMEOUT, text: str = "", message: Message | None = None,
                 code: int = ErrorCode.Unknown):
        self.status = status
        #: Nack: an ErrorCode value.
        self.code = code
        self.text = text
        #: The reply (verified), for Ack and Nack.
        self.message = message

    @property
    def ok(self) -> bool:
        return self.status == Reply.ACK

    def __repr__(self) -> str:
        return f"<Reply {self.status} {self.text!r}>"


class DeviceEntry(NamedTuple):
    """One device as the node lists it."""
    addr: Address
    robot_name: str
    driver: str

    def text(self) -> str:
        """"r0/position2d:0" (robot name when there is one)."""
        return format_address(self.addr, self.robot_name)


def describe_error(msg: Message) -> str:
    e = msg.body_as(_err.Error)
    if e is None:
        return "refused"
    return _text(e.Text()) or _ERROR_NAMES.get(e.Code(), "Unknown")


class Client:
    """A connection to one node or simulator."""

    def __init__(self, host: str, port: int = DEFAULT_PORT, *, name: str = "troupe-python",
                 limits: Limits = Limits(), reconnect: bool = True, reconnect_min: float = 0.1,
                 reconnect_max: float = 2.0, udp_data: bool = False):
        """`name` shows in the node's log; `reconnect` re-establishes a lost
        connection by itself, waiting from reconnect_min doubling to
        reconnect_max seconds between attempts; `udp_data` asks the node to
        send Data as UDP datagrams (latest wins) instead of TCP."""
        self.host, self.port, self.name = host, port, name
        self.limits = limits
        self.reconnect, self.reconnect_min, self.reconnect_max = reconnect, reconnect_min, reconnect_max
        self.udp_data = udp_data
        #: The last problem: resolution, connection, a Nack, an Error from the node.
        self.error = ""
        #: The node's name from its Hello.
        self.node_name = ""
        #: Node clock minus this process's monotonic clock, us (TimeSync). Add it to now_us() for node time.
        self.clock_offset_us = 0
        #: Successful connections so far (1 after the first connect).
        self.connections = 0
        self._verifier = Verifier(limits=limits)
        self._writer = MessageWriter()
        self._state = _IDLE
        self._sock: socket.socket | None = None
        self._udp: socket.socket | None = None
        self._udp_port = 0
        self._reader = FrameReader(limits.max_frame_bytes)
        self._out = bytearray()
        self._seq = 0
        self._reconnect_at = 0.0
        self._backoff = 0.0
        self._time_sync_seq = 0
        self._opened: dict[Address, tuple[int, int]] = {}
        self._proxies: list[weakref.ref] = []
        self._handlers: dict[int, Callable[[Message], None]] = {}
        self._next_handler = 1
        self._awaited_seq = 0
        self._awaited: Reply | None = None

    # ---- Connection ---------------------------------------------------------

    def connect(self, timeout: float = 5.0) -> bool:
        """Connects and waits for the node's Hello. False with `error` when that
        fails (with reconnect on, later attempts continue in spin_once())."""
        if self._state == _IDLE and not self._start_connect():
            return False
        deadline = time.monotonic() + max(timeout, 0.0)
        while self._state in (_CONNECTING, _HANDSHAKE):
            left = deadline - time.monotonic()
            if left <= 0:
                self.error = f"timed out connecting to {self.host}:{self.port}"
                return False
            self.spin_once(left)
        return self.connected

    @property
    def connected(self) -> bool:
        return self._state == _CONNECTED

    def shutdown(self) -> None:
        """Closes the connection for good (no reconnect)."""
        self.reconnect = False
        self._drop("closed by the client")
        if self._udp is not None:
            self._udp.close()
            self._udp = None

    def __enter__(self) -> "Client":
        return self

    def __exit__(self, *exc) -> None:
        self.shutdown()

    def sync(self, timeout: float = 2.0) -> bool:
        """A round trip (TimeSync): when it returns True, everything sent before
        was handled and any reply it caused has arrived. Refreshes clock_offset_us."""
        seq = self._next_seq()
        b = self._writer.start()
        body = self._time_sync_body(b)
        if not self._send(Address(0, 0, 0), Kind.TimeSync, seq, Body.TimeSync, body):
            return False
        return self._wait_reply(seq, timeout).ok

    # ---- Devices --------------------------------------------------------------

    def device_list(self, timeout: float = 2.0) -> list[DeviceEntry] | None:
        """The node's devices, or None (see error)."""
        seq = self._next_seq()
        if not self._send(Address(0, 0, 0), Kind.DeviceList, seq):
            return None
        r = self._wait_reply(seq, timeout)
        listing = r.message.body_as(_dl.DeviceList) if r.ok and r.message else None
        if listing is None:
            return None
        out = []
        for i in range(listing.DevicesLength()):
            d = listing.Devices(i)
            a = d.Addr()
            if a is not None:
                out.append(DeviceEntry(Address(a.Robot(), a.Iface(), a.Index()), _text(d.RobotName()),
                                       _text(d.Driver())))
        return out

    def resolve(self, spec: str, timeout: float = 2.0) -> Address | None:
        """Resolves "[ROBOT/]INTERFACE:INDEX"; robot names go through the device
        list. Raises ValueError for text that is no address at all."""
        parsed = parse_device(spec)
        robot = robot_number(parsed.robot)
        if robot < 0:
            devices = self.device_list(timeout)
            if devices is None:
                return None
            robot = next((d.addr.robot for d in devices if d.robot_name == parsed.robot), -1)
            if robot < 0:
                self.error = f"no robot named '{parsed.robot}' on {self.host}"
                return None
        return Address(robot, parsed.iface, parsed.index)

    def open(self, addr: Address, access: int = Access.All, delivery: int = Delivery.Push,
             timeout: float = 2.0) -> bool:
        """Opens a device and waits for the Ack. The device is remembered and
        opened again after every reconnect, whether this call succeeded or not."""
        self._opened[addr] = (access, delivery)
        seq = self._next_seq()
        b = self._writer.start()
        body = self._open_body(b, access, delivery)
        if not self._send(addr, Kind.Open, seq, Body.Open, body):
            return False
        return self._wait_reply(seq, timeout).ok

    def close(self, addr: Address, timeout: float = 2.0) -> bool:
        """Closes a device (it is no longer re-opened after a reconnect)."""
        self._opened.pop(addr, None)
        seq = self._next_seq()
        return self._send(addr, Kind.Close, seq) and self._wait_reply(seq, timeout).ok

    def pull(self, addr: Address, timeout: float = 2.0) -> bool:
        """Asks for the device's latest data; it reaches the proxies and handlers
        before this returns True."""
        seq = self._next_seq()
        return self._send(addr, Kind.Pull, seq) and self._wait_reply(seq, timeout).ok

    # ---- Sending --------------------------------------------------------------

    def begin(self):
        """Starts a body: build it in the returned flatbuffers.Builder, then pass
        its offset to command() or request()."""
        return self._writer.start()

    def command(self, addr: Address, subtype: int, body_type: int = Body.NONE, body: int = 0) -> bool:
        """Sends a command (no reply). False when not connected."""
        return self._send(addr, Kind.Command, self._next_seq(), body_type, body, subtype)

    def request(self, addr: Address, subtype: int, body_type: int = Body.NONE, body: int = 0,
                timeout: float = 2.0) -> Reply:
        """Sends a request and waits for its Ack or Nack."""
        seq = self._next_seq()
        if not self._send(addr, Kind.Request, seq, body_type, body, subtype):
            return Reply(Reply.DISCONNECTED, self.error)
        return self._wait_reply(seq, timeout)

    def send_frame(self, frame: bytes) -> bool:
        """Sends a prebuilt frame as it is (tools, tests)."""
        return self._queue(frame)

    # ---- Receiving ------------------------------------------------------------

    def add_data_handler(self, handler: Callable[[Message], None]) -> int:
        """Calls handler(message) for every Data message, after the proxies saw
        it. Returns an id for remove_data_handler()."""
        hid = self._next_handler
        self._next_handler += 1
        self._handlers[hid] = handler
        return hid

    def remove_data_handler(self, hid: int) -> None:
        self._handlers.pop(hid, None)

    # ---- Running --------------------------------------------------------------

    def spin_once(self, timeout: float) -> bool:
        """Waits up to `timeout` seconds for traffic and dispatches it (and
        reconnects when due). True when some message arrived."""
        fds = self.poll_fds()
        wait = timeout
        timer = self.next_timeout()
        if timer is not None and (wait is None or wait < 0 or timer < wait):
            wait = timer
        if not fds:
            if wait is None or wait < 0:
                return False
            time.sleep(wait)
            self.process([])
            return False
        poller = select.poll()
        for fd, events in fds:
            poller.register(fd, events)
        ready = poller.poll(None if wait is None or wait < 0 else int(wait * 1000 + 0.999))
        self.process(ready)
        return any(ev & select.POLLIN for _, ev in ready)

    def spin_for(self, seconds: float) -> None:
        """Dispatches traffic for `seconds`."""
        deadline = time.monotonic() + seconds
        while (left := deadline - time.monotonic()) > 0:
            self.spin_once(left)

    def poll_fds(self) -> list[tuple[int, int]]:
        """(fd, poll events) to wait on, for a caller's own poll loop."""
        fds = []
        if self._sock is not None:
            events = select.POLLIN
            if self._state == _CONNECTING or self._out:
                events |= select.POLLOUT
            fds.append((self._sock.fileno(), events))
        if self._udp is not None:
            fds.append((self._udp.fileno(), select.POLLIN))
        return fds

    def next_timeout(self) -> float | None:
        """Seconds until process() must run even without events (None: no deadline)."""
        if self._state != _IDLE or not self._reconnect_at:
            return None
        return max(0.0, self._reconnect_at - time.monotonic())

    def process(self, ready: list[tuple[int, int]]) -> None:
        """Handles what poll() reported as (fd, revents) pairs, then timers."""
        for fd, revents in ready:
            if self._sock is not None and fd == self._sock.fileno():
                if self._state == _CONNECTING:
                    err = self._sock.getsockopt(socket.SOL_SOCKET, socket.SO_ERROR)
                    if err:
                        self._disconnect(f"cannot connect to {self.host}:{self.port}: {os.strerror(err)}")
                        continue
                    self._on_connected()
                if revents & select.POLLOUT:
                    self._flush()
                if self._sock is not None and revents & (select.POLLIN | select.POLLHUP | select.POLLERR):
                    self._read_tcp()
            elif self._udp is not None and fd == self._udp.fileno() and revents & select.POLLIN:
                self._read_udp()
        if self._state == _IDLE and self._reconnect_at and time.monotonic() >= self._reconnect_at:
            self._start_connect()

    # ---- Internals ------------------------------------------------------------

    def _next_seq(self) -> int:
        self._seq = (self._seq + 1) & 0xFFFFFFFF or 1
        return self._seq

    def _start_connect(self) -> bool:
        self._reconnect_at = 0.0
        try:
            found = socket.getaddrinfo(self.host, self.port, type=socket.SOCK_STREAM)
        except (socket.gaierror, UnicodeError) as e:
            self.error = f"cannot resolve host '{self.host}': {e.strerror if hasattr(e, 'strerror') else e}"
            self._schedule_reconnect()
            return False
        last = ""
        for family, kind, proto, _, sockaddr in found:
            s = socket.socket(family, kind, proto)
            s.setblocking(False)
            s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            rc = s.connect_ex(sockaddr)
            if rc in (0, errno.EINPROGRESS):
                self._sock = s
                break
            last = os.strerror(rc)
            s.close()
        if self._sock is None:
            self.error = f"cannot connect to {self.host}:{self.port}: {last}"
            self._schedule_reconnect()
            return False
        if self.udp_data and self._udp is None:
            self._udp = socket.socket(found[0][0], socket.SOCK_DGRAM)
            self._udp.setblocking(False)
            self._udp.bind(("", 0))
            self._udp_port = self._udp.getsockname()[1]
        self._state = _CONNECTING
        return True

    def _time_sync_body(self, b) -> int:
        _ts.TimeSyncStart(b)
        _ts.TimeSyncAddClientSendUs(b, now_us())
        return _ts.TimeSyncEnd(b)

    def _open_body(self, b, access: int, delivery: int) -> int:
        _open.OpenStart(b)
        _open.OpenAddAccess(b, access)
        _open.OpenAddDelivery(b, delivery)
        return _open.OpenEnd(b)

    def _on_connected(self) -> None:
        self._state = _HANDSHAKE
        w = MessageWriter()
        b = w.start()
        name = b.CreateString(self.name)
        _hello.HelloStart(b)
        _hello.HelloAddProtocolVersion(b, PROTOCOL_VERSION)
        _hello.HelloAddName(b, name)
        _hello.HelloAddMaxFrameBytes(b, self.limits.max_frame_bytes)
        _hello.HelloAddUdpPort(b, self._udp_port)
        _hello.HelloAddClockUs(b, now_us())
        self._queue(w.finish(Address(0, 0, 0), Kind.Hello, 0, 0, None, Body.Hello, _hello.HelloEnd(b)))
        self._time_sync_seq = self._next_seq()
        b = w.start()
        self._queue(w.finish(Address(0, 0, 0), Kind.TimeSync, 0, self._time_sync_seq, None, Body.TimeSync,
                             self._time_sync_body(b)))
        # Devices opened before a reconnect are opened again; their Acks need
        # no waiting (a Nack shows up in error).
        for addr, (access, delivery) in self._opened.items():
            b = w.start()
            self._queue(w.finish(addr, Kind.Open, 0, self._next_seq(), None, Body.Open,
                                 self._open_body(b, access, delivery)))

    def _drop(self, why: str) -> None:
        if self._sock is not None:
            self._sock.close()
        self._sock = None
        self._state = _IDLE
        self.error = why
        self._reader = FrameReader(self.limits.max_frame_bytes)
        self._out.clear()
        if self._awaited_seq and self._awaited is None:
            self._awaited = Reply(Reply.DISCONNECTED, why)

    def _disconnect(self, why: str) -> None:
        self._drop(why)
        self._schedule_reconnect()

    def _schedule_reconnect(self) -> None:
        if not self.reconnect:
            return
        self._backoff = self.reconnect_min if not self._backoff else min(self._backoff * 2, self.reconnect_max)
        self._reconnect_at = time.monotonic() + self._backoff

    def _read_tcp(self) -> None:
        for _ in range(16):
            if self._sock is None:
                return
            try:
                data = self._sock.recv(_READ_BYTES)
            except (BlockingIOError, InterruptedError):
                return
            except OSError as e:
                self._disconnect(f"connection to {self.host} lost: {e.strerror}")
                return
            if not data:
                # Keep the node's own explanation if it sent one before closing.
                keep = self.error.startswith("node closed")
                self._disconnect(self.error if keep else f"connection to {self.host} closed by the node")
                return
            self._reader.feed(data)
            while (frame := self._reader.next()) is not None:
                self._dispatch(frame)
                if self._sock is None:
                    return
            if self._reader.too_large:
                self._disconnect(f"node sent a frame over the limit ({self._reader.announced_bytes} bytes)")
                return

    def _read_udp(self) -> None:
        while True:
            try:
                data = self._udp.recv(65536)
            except (BlockingIOError, InterruptedError, OSError):
                return
            try:
                msg = decode(data, self._verifier)
            except Exception:  # noqa: BLE001 - a datagram is noise unless it verifies
                continue
            # Only Data travels by datagram; anything else is noise.
            if msg.header.kind == Kind.Data:
                self._deliver(msg)

    def _dispatch(self, frame: bytes) -> None:
        # The runtime has no verifier: ours runs first, and anything a
        # malformed frame still makes the decoders raise closes the
        # connection instead of escaping to the caller.
        try:
            msg = decode(frame, self._verifier)
        except Exception as e:  # noqa: BLE001
            self._disconnect(f"bad frame from the node: {e}")
            return
        h = msg.header
        kind = h.kind
        if kind == Kind.Data:
            self._deliver(msg)
        elif kind == Kind.Hello:
            hello = msg.body_as(_hello.Hello)
            if hello is None:
                return
            if hello.ProtocolVersion() != PROTOCOL_VERSION:
                self._disconnect(f"node speaks protocol {hello.ProtocolVersion()}, this client {PROTOCOL_VERSION}")
                return
            self.node_name = _text(hello.Name())
            self._state = _CONNECTED
            self.connections += 1
            self._backoff = 0.0
        elif kind == Kind.TimeSync:
            if self._awaited_seq and h.seq == self._awaited_seq and self._awaited is None:
                self._awaited = Reply(Reply.ACK, message=msg)
            t = msg.body_as(_ts.TimeSync)
            if t is not None and h.seq in (self._time_sync_seq, self._awaited_seq):
                t3 = now_us()
                self.clock_offset_us = ((t.NodeRecvUs() - t.ClientSendUs()) + (t.NodeSendUs() - t3)) // 2
        elif kind in (Kind.Ack, Kind.Nack, Kind.DeviceList):
            if kind == Kind.Nack:
                self.error = describe_error(msg)
            if self._awaited_seq and h.seq == self._awaited_seq and self._awaited is None:
                if kind == Kind.Nack:
                    e = msg.body_as(_err.Error)
                    self._awaited = Reply(Reply.NACK, self.error, msg, e.Code() if e else ErrorCode.Unknown)
                else:
                    self._awaited = Reply(Reply.ACK, message=msg)
        elif kind == Kind.Error:
            # The node closes the connection after an Error; remember why.
            self.error = "node closed the connection: " + describe_error(msg)

    def _deliver(self, msg: Message) -> None:
        addr = msg.header.addr
        alive = []
        for ref in self._proxies:
            proxy = ref()
            if proxy is None:
                continue
            alive.append(ref)
            if proxy.address == addr:
                try:
                    proxy._receive(msg)
                except Exception as e:  # noqa: BLE001 - verified yet undecodable: treat as a bad frame
                    self._disconnect(f"bad frame from the node: {type(proxy).__name__} could not read it: {e}")
                    return
        self._proxies = alive
        for handler in list(self._handlers.values()):
            handler(msg)

    def _flush(self) -> None:
        if self._sock is None or self._state == _CONNECTING:
            return
        while self._out:
            try:
                n = self._sock.send(self._out)
            except (BlockingIOError, InterruptedError):
                return
            except OSError as e:
                self._disconnect(f"connection to {self.host} lost: {e.strerror}")
                return
            del self._out[:n]

    def _queue(self, frame: bytes) -> bool:
        if self._state == _IDLE:
            self.error = f"not connected to {self.host}"
            return False
        self._out += frame
        self._flush()
        return self._sock is not None

    def _send(self, addr: Address, kind: int, seq: int, body_type: int = Body.NONE, body: int = 0,
              subtype: int = 0) -> bool:
        if self._state == _IDLE:
            self.error = f"not connected to {self.host}"
            return False
        return self._queue(self._writer.finish(addr, kind, subtype, seq, None, body_type, body))

    def _wait_reply(self, seq: int, timeout: float) -> Reply:
        self._awaited_seq, self._awaited = seq, None
        deadline = time.monotonic() + max(timeout, 0.0)
        while self._awaited is None:
            left = deadline - time.monotonic()
            if left <= 0:
                break
            self.spin_once(left)
        reply = self._awaited
        if reply is None:
            reply = Reply(Reply.TIMEOUT, f"no reply within {timeout * 1000:.0f} ms")
            self.error = reply.text
        self._awaited_seq, self._awaited = 0, None
        return reply

    def _add_proxy(self, proxy) -> None:
        self._proxies.append(weakref.ref(proxy))

    def _remove_proxy(self, proxy) -> None:
        self._proxies = [r for r in self._proxies if r() is not None and r() is not proxy]
