"""The Python client in secure sessions, end to end as a user sets them up:
`troupe keygen` for the node and its clients, a real troupe-node whose
config names its key and its clients with their rights, and troupe.Client
with an identity. Then what must be refused: an unknown client key, a node
holding another key than the one we know for it, a plain client, key files
others can read, a read-only client's command, and the node's messages
replayed, altered or truncated on the way by a man in the middle."""

import json
import os
import select
import shutil
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import unittest
import zlib

import helpers
import troupe
from troupe.wire.Cell import Cell
from troupe.wire.ErrorCode import ErrorCode
from troupe.wire.Position2dReqSub import Position2dReqSub

# The map:0 the node serves: one tile of the largest size a MapTile request
# takes, so its reply (65,536 bytes of cells) is over the 65,519 bytes of
# plaintext one Noise message holds.
MAP_CELLS = 512
# Hang guard for waits on the node, s (a bound on a failing test).
WAIT = 10.0


def spin_until(client: troupe.Client, done, timeout: float = WAIT) -> bool:
    return helpers.spin_until(client, done, timeout)


def write_map_png(path: str) -> None:
    """A MAP_CELLS square grey PNG whose cell (x, y) is occupied (black) where
    x < y, free (white) elsewhere: y grows upwards, so the image's top row is
    map row MAP_CELLS - 1."""
    n = MAP_CELLS
    rows = b"".join(b"\x00" + bytes(0 if x < n - 1 - r else 255 for x in range(n)) for r in range(n))

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", n, n, 8, 0, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


class Relay(threading.Thread):
    """A man in the middle on loopback: one connection passed between a client
    and the node, with the node's transport message number `index` (counted
    from 0 after the handshake, as its nonce) replayed, altered or truncated
    on the way (`tamper` None: passed untouched)."""

    def __init__(self, node_port: int, tamper: str | None, index: int = 3):
        super().__init__(daemon=True)
        self.node_port, self.tamper, self.index = node_port, tamper, index
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.port = self.listener.getsockname()[1]
        self.tampered = False
        self.stopping = False

    def run(self) -> None:
        client, _ = self.listener.accept()
        node = socket.create_connection(("127.0.0.1", self.node_port))
        pending, count = bytearray(), 0  # count: the node's Noise messages, its handshake message included
        try:
            while not self.stopping:
                ready, _, _ = select.select([client, node], [], [], 0.05)
                if client in ready:
                    data = client.recv(65536)
                    if not data:
                        return
                    node.sendall(data)
                if node in ready:
                    data = node.recv(65536)
                    if not data:
                        return
                    pending += data
                    out = bytearray()
                    while len(pending) >= 2 and len(pending) >= 2 + int.from_bytes(pending[:2], "big"):
                        n = int.from_bytes(pending[:2], "big")
                        message = bytes(pending[2:2 + n])
                        del pending[:2 + n]
                        out += self.passed(message, count - 1)
                        count += 1
                    client.sendall(out)
        except OSError:
            return  # the client hung up
        finally:
            client.close()
            node.close()

    def passed(self, message: bytes, number: int) -> bytes:
        """What goes on to the client for the node's `message`."""
        framed = len(message).to_bytes(2, "big") + message
        if number != self.index or self.tamper is None:
            return framed
        self.tampered = True
        if self.tamper == "replay":
            return framed + framed
        if self.tamper == "alter":
            flipped = bytearray(message)
            flipped[len(flipped) // 2] ^= 0x04
            return len(flipped).to_bytes(2, "big") + flipped
        cut = message[:-1]  # truncate: one byte less, its length told
        return len(cut).to_bytes(2, "big") + cut

    def stop(self) -> None:
        self.stopping = True
        self.listener.close()
        self.join(WAIT)


class SecureNode(unittest.TestCase):
    """A secure troupe-node: the laptop may do everything, the monitor only read."""

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="troupe-py-secure-")
        for name in ("node", "laptop", "stranger", "monitor"):
            r = subprocess.run([helpers.TROUPE_CLI, "keygen", self.key(name)], capture_output=True, text=True)
            self.assertEqual(r.returncode, 0, r.stderr)
        # Keys are found from the config's folder, a driver's files from the
        # node's working folder: the map is named in full.
        write_map_png(self.key("map.png"))
        self.port = helpers.free_port()
        self.host = f"127.0.0.1:{self.port}"
        config = os.path.join(self.dir, "node.json")
        with open(config, "w") as f:
            f.write(f"""{{
  "name": "secure-py", "listen": "127.0.0.1", "port": {self.port},
  "key": "node",
  "clients": [ {{ "key": "laptop.pub" }}, {{ "key": "monitor.pub", "read": ["*"] }} ],
  "drivers": [
    {{ "driver_type": "kinematic", "driver": {{ "rate_hz": 20 }}, "provides": ["position2d:0"] }},
    {{ "driver_type": "mapfile", "driver": {{ "file": {json.dumps(self.key("map.png"))}, "resolution": 0.1 }},
      "provides": ["map:0"] }}
  ] }}""")
        self.node = helpers.NodeProcess([helpers.TROUPE_NODE, config], self.port).start()
        self.clients = []

    def tearDown(self):
        for c in self.clients:
            c.shutdown()
        self.assertEqual(self.node.stop(), 0, "troupe-node did not stop cleanly")
        shutil.rmtree(self.dir)

    def key(self, name: str) -> str:
        return os.path.join(self.dir, name)

    def client(self, identity: str, node_key: str | None = "node.pub", port: int | None = None,
               **options) -> troupe.Client:
        c = troupe.Client("127.0.0.1", port or self.port, name="py-secure", identity=self.key(identity),
                          node_key=self.key(node_key) if node_key else None, **options)
        self.clients.append(c)
        return c

    def node_key_hex(self, name: str) -> str:
        with open(self.key(name + ".pub")) as f:
            return f.read().split()[1]

    def expect_laptop_served(self) -> None:
        """The node still serves its known client after a refusal."""
        laptop = self.client("laptop")
        self.assertTrue(laptop.connect(), laptop.error)
        self.assertEqual([d.text() for d in laptop.device_list()], ["position2d:0", "map:0"])


class KnownClient(SecureNode):
    def test_it_reads_a_device_and_its_command_moves_the_base(self):
        laptop = self.client("laptop")
        self.assertTrue(laptop.connect(), laptop.error)
        self.assertTrue(laptop.secure)
        self.assertEqual(laptop.node_name, "secure-py")
        base = troupe.Position2dProxy(laptop)
        self.assertTrue(base.is_open, laptop.error)
        self.assertTrue(spin_until(laptop, lambda: base.samples >= 3), laptop.error)
        self.assertEqual(base.x, 0.0)
        self.assertTrue(base.set_velocity(0.5, 0.0, 0.0))
        self.assertTrue(spin_until(laptop, lambda: base.x > 0.1), f"the base did not move: {laptop.error}")
        self.assertTrue(self.node.wait_for_log(f"secure session with key {self.node_key_hex('laptop')}"),
                        self.node.stderr())

    def test_a_frame_larger_than_one_noise_message_is_reassembled(self):
        laptop = self.client("laptop")
        self.assertTrue(laptop.connect(), laptop.error)
        grid = troupe.MapProxy(laptop, index=0).fetch(tile=MAP_CELLS)
        self.assertIsNotNone(grid, laptop.error)
        self.assertEqual((grid.width, grid.height), (MAP_CELLS, MAP_CELLS))
        wrong = [(x, y) for y in range(MAP_CELLS) for x in range(MAP_CELLS)
                 if grid.cells[y * MAP_CELLS + x] != (Cell.Occupied if x < y else Cell.Free)]
        self.assertEqual(wrong[:5], [])
        self.assertTrue(laptop.connected)

    def test_the_known_nodes_file_names_the_nodes_key(self):
        saved = os.environ.get("XDG_CONFIG_HOME")
        os.environ["XDG_CONFIG_HOME"] = self.key("config")
        try:
            with self.assertRaisesRegex(troupe.KeyFileError, f"no key known for {self.host}"):
                self.client("laptop", node_key=None)
            os.makedirs(self.key("config/troupe"))
            with open(self.key("config/troupe/known_nodes"), "w") as f:
                f.write(f"# nodes this laptop talks to\nother:6665 {self.node_key_hex('node')}\n"
                        f"{self.host} {self.node_key_hex('node')}\n")
            laptop = self.client("laptop", node_key=None)
        finally:
            if saved is None:
                del os.environ["XDG_CONFIG_HOME"]
            else:
                os.environ["XDG_CONFIG_HOME"] = saved
        self.assertTrue(laptop.connect(), laptop.error)
        self.assertEqual(laptop.device_list()[0].text(), "position2d:0")

    def test_key_files_that_cannot_serve_are_refused_before_connecting(self):
        os.chmod(self.key("laptop"), 0o644)
        with self.assertRaisesRegex(troupe.KeyFileError, r"permissions 0644 let others read this secret key; "
                                    r"chmod 600"):
            self.client("laptop")
        with open(self.key("notes"), "w") as f:
            f.write("troupe-x25519 not a secret\n")
        os.chmod(self.key("notes"), 0o600)
        with self.assertRaisesRegex(troupe.KeyFileError, "notes: not a secret key file"):
            self.client("notes")
        with self.assertRaisesRegex(troupe.KeyFileError, "not a public key file"):
            self.client("monitor", node_key="node.json")
        with self.assertRaisesRegex(ValueError, "needs identity=FILE"):
            troupe.Client("127.0.0.1", self.port, node_key=self.key("node.pub"))


class Refused(SecureNode):
    def test_an_unknown_client_key(self):
        stranger = self.client("stranger", reconnect=False)
        self.assertFalse(stranger.connect())
        self.assertIn("during the secure handshake", stranger.error)
        self.assertIn("does not accept our key", stranger.error)
        self.assertTrue(self.node.wait_for_log(f"key {self.node_key_hex('stranger')} is not among the node's clients"),
                        self.node.stderr())
        self.expect_laptop_served()

    def test_a_node_whose_key_differs_from_the_one_we_know(self):
        laptop = self.client("laptop", node_key="stranger.pub", reconnect=False)
        self.assertFalse(laptop.connect())
        self.assertIn("during the secure handshake: the node's key differs from the one we know for it",
                      laptop.error)
        self.assertTrue(self.node.wait_for_log("does not hold this node's public key"), self.node.stderr())
        self.expect_laptop_served()

    def test_a_plain_client(self):
        plain = troupe.Client("127.0.0.1", self.port, reconnect=False)
        self.clients.append(plain)
        self.assertFalse(plain.connect())
        self.assertFalse(plain.secure)
        self.assertTrue(self.node.wait_for_log("did not open a secure session"), self.node.stderr())
        self.expect_laptop_served()

    def test_a_secure_client_meeting_a_plain_node(self):
        port = helpers.free_port()
        with helpers.kinematic_node(port):
            laptop = self.client("laptop", port=port, reconnect=False)
            self.assertFalse(laptop.connect())
            self.assertIn("did not answer with a secure handshake", laptop.error)
            self.assertIn("an insecure node?", laptop.error)


class WithoutPyNaCl(unittest.TestCase):
    def test_a_plain_client_needs_no_pynacl_and_a_secure_one_says_what_it_needs(self):
        port = helpers.free_port()
        # A Python where PyNaCl cannot be imported (None in sys.modules
        # stops an import), in a process of its own.
        script = f"""
import sys
sys.modules["nacl"] = None
import troupe
plain = troupe.Client("127.0.0.1", {port}, reconnect=False)
assert plain.connect(), plain.error
print([d.text() for d in plain.device_list()])
try:
    troupe.Client("127.0.0.1", {port}, identity="laptop", node_key=64 * "0")
except ImportError as e:
    print(e)
"""
        with helpers.kinematic_node(port):
            r = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stdout, "['position2d:0']\nsecure sessions need PyNaCl (Debian: apt-get install "
                                   "python3-nacl)\n")


class Rights(SecureNode):
    def test_a_read_only_client_reads_and_its_command_gets_nack_forbidden(self):
        monitor = self.client("monitor")
        self.assertTrue(monitor.connect(), monitor.error)
        base = troupe.Position2dProxy(monitor)
        self.assertTrue(base.is_open, monitor.error)
        self.assertTrue(spin_until(monitor, lambda: base.samples >= 2), monitor.error)
        # A command has no reply when carried out: a refusal is a Nack before
        # the answer to a round trip sent after it.
        self.assertTrue(base.set_velocity(0.5, 0.0, 0.0))
        self.assertTrue(monitor.sync(), monitor.error)
        self.assertIsNotNone(monitor.last_nack, "no Nack for the refused command")
        self.assertEqual(monitor.last_nack.code, ErrorCode.Forbidden)
        self.assertEqual(monitor.last_nack.code_name, "Forbidden")
        self.assertIn("this client may not command position2d:0", monitor.error)
        reply = monitor.request(base.address, Position2dReqSub.Geometry)
        self.assertEqual((reply.status, reply.code_name), (troupe.Reply.NACK, "Forbidden"))
        self.assertIn("this client may not request position2d:0", reply.text)
        # The connection goes on, and nothing moved.
        self.assertTrue(monitor.connected)
        seen = base.samples
        self.assertTrue(spin_until(monitor, lambda: base.samples >= seen + 3), monitor.error)
        self.assertEqual((base.x, base.velocity.x), (0.0, 0.0))


class ManInTheMiddle(SecureNode):
    """The node's transport messages changed on the way end the session."""

    def through_relay(self, tamper: str | None) -> tuple[troupe.Client, troupe.Position2dProxy, Relay]:
        relay = Relay(self.port, tamper)
        relay.start()
        self.addCleanup(relay.stop)
        laptop = self.client("laptop", port=relay.port, reconnect=False)
        self.assertTrue(laptop.connect(), laptop.error)
        base = troupe.Position2dProxy(laptop)
        return laptop, base, relay

    def test_untouched_the_relay_passes_the_session(self):
        laptop, base, relay = self.through_relay(None)
        self.assertTrue(spin_until(laptop, lambda: base.samples >= 10), laptop.error)
        self.assertTrue(laptop.connected)

    def ends_the_session(self, tamper: str, error: str) -> None:
        laptop, base, relay = self.through_relay(tamper)
        self.assertTrue(spin_until(laptop, lambda: not laptop.connected), "the session went on")
        self.assertTrue(relay.tampered)
        self.assertIn(f"bad bytes from 127.0.0.1:{relay.port}: {error}", laptop.error)
        self.assertEqual(laptop.state, "idle")
        self.expect_laptop_served()

    def test_a_replayed_message(self):
        self.ends_the_session("replay", "transport message 4 does not authenticate (altered, replayed, reordered or "
                                        "a message dropped): session ended")

    def test_an_altered_message(self):
        self.ends_the_session("alter", "transport message 3 does not authenticate")

    def test_a_truncated_message(self):
        self.ends_the_session("truncate", "transport message 3 does not authenticate")


if __name__ == "__main__":
    unittest.main()
