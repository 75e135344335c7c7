"""The Python client: a connection to a node or simulator, shaped like the
C++ one (wire/client/client.h). Use it blocking (connect(), request(),
spin_once()) or from your own poll loop (poll_fds(), process(),
next_timeout()). A lost connection is noticed (a keep-alive finds a silent
node) and re-established with backoff; devices opened before are opened
again and proxies keep working.

The connection goes through the states of the C++ connection core
(wire/connection/connection.h; wire/README.md, "Connection lifecycle"), by
the same names: idle, waiting, connecting (every address of the host, in
order, RFC 8305 style), handshake, up. This is its own implementation of
them, not a binding. Given an identity it speaks secure sessions (Noise IK,
troupe.noise): the handshake comes before the Hello, and every byte after it
travels sealed.

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
from .keys import find_known_node, known_nodes_path, read_public_key, read_secret_key
from .message import PROTOCOL_VERSION, Message, MessageWriter, decode, now_us
from .verify import Limits, Verifier

_ERROR_NAMES = {v: k for k, v in vars(ErrorCode).items() if not k.startswith("_")}
_READ_BYTES = 64 * 1024

#: The connection's states (Client.state), named as the C++ core names them.
IDLE, WAITING, CONNECTING, HANDSHAKE, UP = "idle", "waiting", "connecting", "handshake", "up"
#: RFC 8305's Connection Attempt Delay: the next address is tried when the
#: current one has neither failed nor connected after this long, s.
ATTEMPT_DELAY = 0.25
#: Attempts open at once while connecting.
MAX_ATTEMPTS_IN_FLIGHT = 2


def resolve(host: str, port: int) -> list[tuple[int, tuple]]:
    """The addresses to try for host:port as (family, sockaddr), in the order
    RFC 8305 asks: getaddrinfo's, with address families alternating. Raises
    OSError (socket.gaierror) when there are none."""
    found = [(family, addr) for family, _, _, _, addr in
             socket.getaddrinfo(host.strip("[]"), port, type=socket.SOCK_STREAM)]
    if not found:
        return []
    first = [f for f in found if f[0] == found[0][0]]
    other = [f for f in found if f[0] != found[0][0]]
    out = []
    for i in range(max(len(first), len(other))):
        out += first[i:i + 1] + other[i:i + 1]
    return out


def _address_text(family: int, addr: tuple) -> str:
    return f"[{addr[0]}]:{addr[1]}" if family == socket.AF_INET6 else f"{addr[0]}:{addr[1]}"


class _Attempt:
    """One address being tried."""

    def __init__(self, family: int, addr: tuple):
        self.family, self.addr = family, addr
        self.sock: socket.socket | None = None
        self.why = ""  # why it failed
        self.started = False


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

    @property
    def code_name(self) -> str:
        """The Nack's ErrorCode by name ("Forbidden", "NoSuchDevice", ...)."""
        return _ERROR_NAMES.get(self.code, "Unknown")

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
                 reconnect_max: float = 2.0, udp_data: bool = False, keepalive: float = 2.0,
                 keepalive_timeout: float = 6.0, connect_timeout: float = 10.0,
                 resolver: Callable[[str, int], list[tuple[int, tuple]]] = resolve,
                 identity: str | None = None, node_key: str | None = None):
        """`name` shows in the node's log; `reconnect` re-establishes a lost
        connection by itself, waiting from reconnect_min doubling to
        reconnect_max seconds between attempts; `udp_data` asks the node to
        send Data as UDP datagrams (latest wins) instead of TCP. After
        `keepalive` s without hearing from the node a TimeSync goes out (0:
        never), and a node that answers nothing within `keepalive_timeout` s
        of it is dropped. An attempt (every address, and the handshake) gives
        up after `connect_timeout` s. `resolver(host, port)` gives the
        addresses to try (see resolve()).

        A secure session (wire/README.md, "Secure sessions"): `identity` is our
        secret key file (`troupe keygen NAME` writes one; refused when others
        can read it), `node_key` the node's public key (its NAME.pub, or 64 hex
        digits; default: the node's line in the known-nodes file, see
        troupe.keys.known_nodes_path()). Raises troupe.KeyFileError when a key
        cannot be read, ImportError without PyNaCl. Data then stays on TCP
        (`udp_data` is ignored: a secure node refuses the UDP path)."""
        self.host, self.port, self.name = host, port, name
        self.limits = limits
        self.reconnect, self.reconnect_min, self.reconnect_max = reconnect, reconnect_min, reconnect_max
        self.udp_data = udp_data
        self.keepalive, self.keepalive_timeout, self.connect_timeout = keepalive, keepalive_timeout, connect_timeout
        self.resolver = resolver
        self.target = f"[{host}]:{port}" if ":" in host and not host.startswith("[") else f"{host}:{port}"
        self._identity = self._node_key = None
        if identity is not None or node_key is not None:
            self._read_keys(identity, node_key)
        #: The last problem: resolution, connection, a Nack, an Error from the node.
        self.error = ""
        #: The node's name from its Hello.
        self.node_name = ""
        #: Node clock minus this process's monotonic clock, us (TimeSync). Add it to now_us() for node time.
        self.clock_offset_us = 0
        #: Successful connections so far (1 after the first connect).
        self.connections = 0
        #: The last Nack the node sent, asked for or not (a refused command's
        #: comes unasked): a Reply with its code (Reply.code_name) and text.
        self.last_nack: Reply | None = None
        self._verifier = Verifier(limits=limits)
        self._writer = MessageWriter()
        self._state = IDLE
        self._running = False
        self._sock: socket.socket | None = None
        self._udp: socket.socket | None = None
        self._udp_port = 0
        self._reader = FrameReader(limits.max_frame_bytes)
        self._out = bytearray()   # frames to send (plaintext in a secure session)
        self._wire = bytearray()  # a secure session's bytes to send: Noise messages
        self._session = None      # a secure session's noise.SecureSession, per connection
        self._hello_sent = False
        self._seq = 0
        self._attempts: list[_Attempt] = []
        self._stagger_at = 0.0    # connecting: the next address starts
        self._deadline = 0.0      # connecting, handshake: give up
        self._retry_at = 0.0      # waiting: the next attempt
        self._backoff = 0.0
        self._last_rx = 0.0
        self._ping_seq = 0        # the keep-alive TimeSync
        self._ping_sent = 0.0     # 0: none outstanding
        self._time_sync_seq = 0
        self._opened: dict[Address, tuple[int, int, int]] = {}
        self._proxies: list[weakref.ref] = []
        self._handlers: dict[int, Callable[[Message], None]] = {}
        self._next_handler = 1
        self._awaited_seq = 0
        self._awaited: Reply | None = None

    # ---- Connection ---------------------------------------------------------

    def connect(self, timeout: float = 5.0) -> bool:
        """Connects and waits for the node's Hello. False with `error` when that
        fails (with reconnect on, later attempts continue in spin_once())."""
        if self._state in (IDLE, WAITING):
            self._running = True
            self._begin_attempt()
        deadline = time.monotonic() + max(timeout, 0.0)
        while self._state in (CONNECTING, HANDSHAKE):
            left = deadline - time.monotonic()
            if left <= 0:
                self.error = f"timed out connecting to {self.target}"
                return False
            self.spin_once(left)
        return self.connected

    @property
    def state(self) -> str:
        """idle, waiting, connecting, handshake or up (wire/README.md)."""
        return self._state

    @property
    def connected(self) -> bool:
        return self._state == UP

    @property
    def secure(self) -> bool:
        """Whether this client speaks secure sessions (it was given an identity)."""
        return self._identity is not None

    @property
    def node_key(self) -> bytes | None:
        """The node's public key a secure session expects (32 bytes)."""
        return self._node_key

    def shutdown(self) -> None:
        """Closes the connection for good (no reconnect)."""
        self._running = False
        self._close_attempts()
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
             timeout: float = 2.0, compression: int = 0) -> bool:
        """Opens a device and waits for the Ack. The device is remembered and
        opened again after every reconnect, whether this call succeeded or not.
        `compression` (an ImageCompression value): how a camera should pack its
        images for this client (one that cannot sends raw rows)."""
        self._opened[addr] = (access, delivery, compression)
        seq = self._next_seq()
        b = self._writer.start()
        body = self._open_body(b, access, delivery, compression)
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
            events = select.POLLIN | (select.POLLOUT if self._unsent() else 0)
            fds.append((self._sock.fileno(), events))
            if self._udp is not None:
                fds.append((self._udp.fileno(), select.POLLIN))
        for a in self._attempts:
            if a.sock is not None:
                fds.append((a.sock.fileno(), select.POLLOUT))
        return fds

    def next_timeout(self) -> float | None:
        """Seconds until process() must run even without events (None: no deadline)."""
        at = self._next_deadline()
        return None if at is None else max(0.0, at - time.monotonic())

    def process(self, ready: list[tuple[int, int]]) -> None:
        """Handles what poll() reported as (fd, revents) pairs, then timers."""
        for fd, revents in ready:
            if self._sock is not None and fd == self._sock.fileno():
                if revents & select.POLLOUT:
                    self._flush()
                if self._sock is not None and revents & (select.POLLIN | select.POLLHUP | select.POLLERR):
                    self._read_tcp()
            elif self._udp is not None and fd == self._udp.fileno() and revents & select.POLLIN:
                self._read_udp()
            else:
                for i, a in enumerate(self._attempts):
                    if a.sock is not None and a.sock.fileno() == fd:
                        err = a.sock.getsockopt(socket.SOL_SOCKET, socket.SO_ERROR)
                        if err:
                            self._attempt_failed(i, os.strerror(err))
                        else:
                            self._attempt_connected(i)
                        break
        self._on_time(time.monotonic())

    # ---- Internals ------------------------------------------------------------

    def _next_seq(self) -> int:
        self._seq = (self._seq + 1) & 0xFFFFFFFF or 1
        return self._seq

    def _begin_attempt(self) -> None:
        """Connecting: resolve the host, then try its addresses."""
        now = time.monotonic()
        self._state = CONNECTING
        self._retry_at = 0.0
        self._deadline = now + self.connect_timeout if self.connect_timeout > 0 else 0.0
        try:
            found = self.resolver(self.host, self.port)
        except (OSError, UnicodeError) as e:
            self._fail_attempt(f"cannot resolve host '{self.host}': {getattr(e, 'strerror', None) or e}")
            return
        if not found:
            self._fail_attempt(f"no address for {self.target}")
            return
        self._attempts = [_Attempt(family, addr) for family, addr in found]
        self._start_next()

    def _start_next(self) -> bool:
        """Starts the next untried address (RFC 8305: at once after a failure,
        or when the attempt delay passed); False when none is left."""
        for i, a in enumerate(self._attempts):
            if a.started:
                continue
            a.started = True
            self._stagger_at = time.monotonic() + ATTEMPT_DELAY
            s = socket.socket(a.family, socket.SOCK_STREAM)
            s.setblocking(False)
            s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            a.sock = s
            rc = s.connect_ex(a.addr)
            if rc == 0:
                self._attempt_connected(i)
            elif rc != errno.EINPROGRESS:
                self._attempt_failed(i, os.strerror(rc))
            return True
        self._stagger_at = 0.0
        return False

    def _in_flight(self) -> int:
        return sum(1 for a in self._attempts if a.sock is not None)

    def _attempt_failed(self, i: int, why: str) -> None:
        a = self._attempts[i]
        if a.sock is not None:
            a.sock.close()
            a.sock = None
        a.why = why
        if self._state == CONNECTING and not self._start_next() and self._in_flight() == 0:
            reasons = {x.why for x in self._attempts}
            if len(reasons) == 1:
                self._fail_attempt(f"cannot connect to {self.target}: {why}")
            else:
                each = "; ".join(f"{_address_text(x.family, x.addr)}: {x.why}" for x in self._attempts)
                self._fail_attempt(f"cannot connect to {self.target}: {each}")

    def _attempt_connected(self, i: int) -> None:
        self._sock, self._attempts[i].sock = self._attempts[i].sock, None
        self._close_attempts()
        self._state = HANDSHAKE
        self._last_rx = time.monotonic()
        self._reader = FrameReader(self.limits.max_frame_bytes)
        if self.udp_data and self._udp is None and not self.secure:
            # One socket for both families (IPv6 with IPv4-mapped addresses).
            try:
                self._udp = socket.socket(socket.AF_INET6, socket.SOCK_DGRAM)
                self._udp.setsockopt(socket.IPPROTO_IPV6, socket.IPV6_V6ONLY, 0)
                self._udp.bind(("::", 0))
            except OSError:
                self._udp = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
                self._udp.bind(("", 0))
            self._udp.setblocking(False)
            self._udp_port = self._udp.getsockname()[1]
        self._on_connected()

    def _close_attempts(self) -> None:
        for a in self._attempts:
            if a.sock is not None:
                a.sock.close()
                a.sock = None
        self._attempts = []
        self._stagger_at = 0.0

    def _fail_attempt(self, why: str) -> None:
        self._close_attempts()
        self._drop(why)
        self._schedule_reconnect()

    def _next_deadline(self) -> float | None:
        """When _on_time() must run next (monotonic s), or None."""
        if self._state == WAITING:
            return self._retry_at
        if self._state == CONNECTING:
            untried = any(not a.started for a in self._attempts)
            stagger = self._stagger_at if untried and self._in_flight() < MAX_ATTEMPTS_IN_FLIGHT else 0.0
            times = [t for t in (self._deadline, stagger) if t]
            return min(times) if times else None
        if self._state == HANDSHAKE:
            return self._deadline or None
        if self._state == UP and self.keepalive > 0:
            return self._ping_sent + self.keepalive_timeout if self._ping_sent else self._last_rx + self.keepalive
        return None

    def _on_time(self, now: float) -> None:
        if self._state == WAITING and now >= self._retry_at:
            self._begin_attempt()
        elif self._state == CONNECTING:
            if self._deadline and now >= self._deadline:
                self._fail_attempt(f"no connection with {self.target} within {self.connect_timeout * 1000:.0f} ms")
            elif self._stagger_at and now >= self._stagger_at and self._in_flight() < MAX_ATTEMPTS_IN_FLIGHT:
                self._start_next()
        elif self._state == HANDSHAKE and self._deadline and now >= self._deadline:
            self._disconnect(f"no handshake with {self.target} within {self.connect_timeout * 1000:.0f} ms")
        elif self._state == UP and self.keepalive > 0:
            if self._ping_sent and now >= self._ping_sent + self.keepalive_timeout:
                self._disconnect(f"node silent for {(now - self._last_rx) * 1000:.0f} ms")
            elif not self._ping_sent and now >= self._last_rx + self.keepalive:
                # A TimeSync is the cheapest message every node answers.
                self._ping_seq, self._ping_sent = self._next_seq(), now
                w = MessageWriter()
                b = w.start()
                self._queue(w.finish(Address(0, 0, 0), Kind.TimeSync, 0, self._ping_seq, None, Body.TimeSync,
                                     self._time_sync_body(b)))

    def _time_sync_body(self, b) -> int:
        _ts.TimeSyncStart(b)
        _ts.TimeSyncAddClientSendUs(b, now_us())
        return _ts.TimeSyncEnd(b)

    def _open_body(self, b, access: int, delivery: int, compression: int) -> int:
        _open.OpenStart(b)
        _open.OpenAddAccess(b, access)
        _open.OpenAddDelivery(b, delivery)
        _open.OpenAddCompression(b, compression)
        return _open.OpenEnd(b)

    def _read_keys(self, identity: str | None, node_key: str | None) -> None:
        """The keys of a secure session, read once (as the CLI reads them before
        connecting); the known-nodes file names the node's when node_key does not."""
        if identity is None:
            raise ValueError("a secure session needs identity=FILE (our secret key) with node_key")
        # Imported here: a plain client runs without PyNaCl.
        from . import noise
        self._node_key = (read_public_key(node_key) if node_key is not None
                          else find_known_node(known_nodes_path(), self.target))
        self._identity = noise.keypair_from_secret(read_secret_key(identity))

    def _on_connected(self) -> None:
        """TCP is up. In a secure session the handshake's message 1 goes out and
        the Hello waits for the node's answer; else the Hello goes at once."""
        self._hello_sent = False
        if self.secure:
            from . import noise
            self._session = noise.SecureSession(self._identity, self._node_key)
            self._wire += self._session.begin()
            self._flush()
            return
        self._send_hello()

    def _send_hello(self) -> None:
        """Hello and the first TimeSync go out before anything queued while
        connecting."""
        self._hello_sent = True
        queued, self._out = self._out, bytearray()
        w = MessageWriter()
        b = w.start()
        name = b.CreateString(self.name)
        _hello.HelloStart(b)
        _hello.HelloAddProtocolVersion(b, PROTOCOL_VERSION)
        _hello.HelloAddName(b, name)
        _hello.HelloAddMaxFrameBytes(b, self.limits.max_frame_bytes)
        _hello.HelloAddUdpPort(b, self._udp_port)
        _hello.HelloAddClockUs(b, now_us())
        self._out += w.finish(Address(0, 0, 0), Kind.Hello, 0, 0, None, Body.Hello, _hello.HelloEnd(b))
        self._time_sync_seq = self._next_seq()
        b = w.start()
        self._out += w.finish(Address(0, 0, 0), Kind.TimeSync, 0, self._time_sync_seq, None, Body.TimeSync,
                              self._time_sync_body(b))
        self._out += queued
        self._flush()

    def _on_up(self) -> None:
        """The node's Hello arrived. Devices opened before a reconnect are
        opened again; their Acks need no waiting (a Nack shows up in error)."""
        w = MessageWriter()
        for addr, (access, delivery, compression) in self._opened.items():
            b = w.start()
            self._queue(w.finish(addr, Kind.Open, 0, self._next_seq(), None, Body.Open,
                                 self._open_body(b, access, delivery, compression)))

    def _drop(self, why: str) -> None:
        if self._sock is not None:
            self._sock.close()
        self._sock = None
        self._state = IDLE
        self._ping_sent = 0.0
        self.error = why
        self._reader = FrameReader(self.limits.max_frame_bytes)
        self._out.clear()
        self._wire.clear()
        self._session = None
        if self._awaited_seq and self._awaited is None:
            self._awaited = Reply(Reply.DISCONNECTED, why)

    def _disconnect(self, why: str) -> None:
        self._drop(why)
        self._schedule_reconnect()

    def _schedule_reconnect(self) -> None:
        if not self.reconnect or not self._running:
            self._running = False
            return
        self._backoff = self.reconnect_min if not self._backoff else min(self._backoff * 2, self.reconnect_max)
        self._retry_at = time.monotonic() + self._backoff
        self._state = WAITING

    def _read_tcp(self) -> None:
        for _ in range(16):
            if self._sock is None:
                return
            try:
                data = self._sock.recv(_READ_BYTES)
            except (BlockingIOError, InterruptedError):
                return
            except OSError as e:
                self._disconnect(self._in_handshake(f"connection to {self.host} lost: {e.strerror}"))
                return
            self._last_rx, self._ping_sent = time.monotonic(), 0.0
            if not data:
                # Keep the node's own explanation if it sent one before closing.
                keep = self.error.startswith("node closed")
                self._disconnect(self.error if keep else
                                 self._in_handshake(f"connection to {self.host} closed by the node"))
                return
            if self._session is not None:
                data = self._open_secure(data)
                if data is None:
                    return
            self._reader.feed(data)
            while (frame := self._reader.next()) is not None:
                self._dispatch(frame)
                if self._sock is None:
                    return
            if self._reader.too_large:
                self._disconnect(f"node sent a frame over the limit ({self._reader.announced_bytes} bytes)")
                return

    def _in_handshake(self, why: str) -> str:
        """`why`, and what a connection ending in the secure handshake can mean:
        a secure node answers nothing to a handshake it refuses."""
        if self._session is None or self._session.ready:
            return why
        return (why + " during the secure handshake: the node's key differs from the one we know for it (its key "
                "changed, or another node answers), or it does not accept our key, or it does not speak secure "
                "sessions")

    def _open_secure(self, data: bytes) -> bytes | None:
        """The frame bytes that the Noise messages in `data` carried; None when
        the session failed (the connection is then dropped with the reason)."""
        from .noise import SecureSessionError
        try:
            plain = self._session.inbound(data)
        except SecureSessionError as e:
            self._disconnect(f"bad bytes from {self.target}: {e}")
            return None
        if self._session.ready and not self._hello_sent:
            self._send_hello()
            if self._sock is None:
                return None
        return plain

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
            self._state = UP
            self.connections += 1
            self._backoff = 0.0
            self._on_up()
        elif kind == Kind.TimeSync:
            if h.seq == self._ping_seq:
                return  # the keep-alive's reply: arriving was its job
            if self._awaited_seq and h.seq == self._awaited_seq and self._awaited is None:
                self._awaited = Reply(Reply.ACK, message=msg)
            t = msg.body_as(_ts.TimeSync)
            if t is not None and h.seq in (self._time_sync_seq, self._awaited_seq):
                t3 = now_us()
                self.clock_offset_us = ((t.NodeRecvUs() - t.ClientSendUs()) + (t.NodeSendUs() - t3)) // 2
        elif kind in (Kind.Ack, Kind.Nack, Kind.DeviceList):
            if kind == Kind.Nack:
                self.error = describe_error(msg)
                e = msg.body_as(_err.Error)
                self.last_nack = Reply(Reply.NACK, self.error, msg, e.Code() if e else ErrorCode.Unknown)
            if self._awaited_seq and h.seq == self._awaited_seq and self._awaited is None:
                if kind == Kind.Nack:
                    self._awaited = self.last_nack
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

    def _unsent(self) -> bool:
        """Bytes the socket can take now (a secure session's frames wait for its
        handshake: no point waiting for POLLOUT for them)."""
        if self._session is None:
            return bool(self._out)
        return bool(self._wire) or (self._session.ready and bool(self._out))

    def _flush(self) -> None:
        if self._sock is None:
            return
        buf = self._out
        if self._session is not None:
            # Frames wait in _out until the handshake is done, then go out
            # sealed; _wire holds the Noise messages the socket has not taken.
            if self._session.ready and self._out:
                self._wire += self._session.seal(self._out)
                self._out.clear()
            buf = self._wire
        while buf:
            try:
                n = self._sock.send(buf)
            except (BlockingIOError, InterruptedError):
                return
            except OSError as e:
                self._disconnect(self._in_handshake(f"connection to {self.host} lost: {e.strerror}"))
                return
            del buf[:n]

    def _queue(self, frame: bytes) -> bool:
        """Sends a frame; while connecting it waits and goes out after the Hello."""
        if self._state not in (CONNECTING, HANDSHAKE, UP):
            self.error = f"not connected to {self.host}"
            return False
        self._out += frame
        self._flush()
        return self._state != IDLE and self._state != WAITING

    def _send(self, addr: Address, kind: int, seq: int, body_type: int = Body.NONE, body: int = 0,
              subtype: int = 0) -> bool:
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
