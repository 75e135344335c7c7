"""What the client does with a peer that sends malformed frames. A real node
never does, so a raw TCP peer plays that part here (the client's normal work
is tested against troupe-node in test_client.py): the client drops the
connection with a clear error, raises nothing, and keeps reconnecting."""

import socket
import struct
import threading
import unittest

import sample_frames as S
import troupe
from troupe.wire import Hello as he
from troupe.wire.Body import Body
from troupe.wire.Kind import Kind


class RawPeer:
    """Accepts connections and sends each the given bytes, then waits for the client to go."""

    def __init__(self, payload: bytes):
        self.payload = payload
        self.server = socket.socket()
        self.server.bind(("127.0.0.1", 0))
        self.server.listen()
        self.port = self.server.getsockname()[1]
        self.accepted = 0
        self._thread = threading.Thread(target=self._serve, daemon=True)
        self._thread.start()

    def _serve(self):
        while True:
            try:
                conn, _ = self.server.accept()
            except OSError:
                return
            self.accepted += 1
            with conn:
                conn.sendall(self.payload)
                try:
                    while conn.recv(4096):
                        pass
                except OSError:
                    pass

    def close(self):
        self.server.close()


class BadPeer(unittest.TestCase):
    def test_after_a_bad_frame_the_client_reconnects(self):
        frame = bytearray(S.ranger(beams=10))
        root = struct.unpack_from("<I", frame, 4)[0] + 4
        struct.pack_into("<i", frame, root, 1 << 20)  # the message's vtable far outside
        peer = RawPeer(S.hello() + bytes(frame))
        client = troupe.Client("127.0.0.1", peer.port, reconnect_min=0.02, reconnect_max=0.05)
        try:
            client.connect(2.0)
            for _ in range(400):
                if peer.accepted >= 3:
                    break
                client.spin_once(0.02)
            self.assertGreaterEqual(peer.accepted, 3)
            self.assertGreaterEqual(client.connections, 2)
            self.assertIn("bad frame from the node: Message: vtable outside the frame", client.error)
        finally:
            client.shutdown()
            peer.close()

    def test_errors_name_the_problem(self):
        cases = {
            "bad frame from the node: Message: vtable outside the frame (byte ": self._bad_vtable(),
            "node sent a frame over the limit (2147483000 bytes)": struct.pack("<I", 2147483000) + b"x" * 100,
            "node speaks protocol 9, this client 1": self._hello(version=9),
        }
        for expected, payload in cases.items():
            with self.subTest(expected):
                peer = RawPeer(S.hello() + payload if "protocol" not in expected else payload)
                client = troupe.Client("127.0.0.1", peer.port, reconnect=False)
                client.connect(2.0)
                for _ in range(100):
                    if client.error.startswith(expected[:20]):
                        break
                    client.spin_once(0.02)
                self.assertIn(expected, client.error)
                self.assertFalse(client.connected)
                client.shutdown()
                peer.close()

    def test_random_garbage_after_hello_never_raises(self):
        import random
        rng = random.Random(5)
        for _ in range(30):
            body = bytes(rng.randrange(256) for _ in range(rng.randint(4, 120)))
            payload = S.hello() + struct.pack("<I", len(body)) + body
            peer = RawPeer(payload)
            client = troupe.Client("127.0.0.1", peer.port, reconnect=False)
            client.connect(2.0)
            for _ in range(20):
                client.spin_once(0.01)
            self.assertTrue(client.error.startswith("bad frame from the node") or client.connected, client.error)
            client.shutdown()
            peer.close()

    @staticmethod
    def _bad_vtable() -> bytes:
        frame = bytearray(S.power())
        root = struct.unpack_from("<I", frame, 4)[0] + 4
        struct.pack_into("<i", frame, root, -100000)
        return bytes(frame)

    @staticmethod
    def _hello(version: int) -> bytes:
        w = troupe.MessageWriter()
        b = w.start()
        he.HelloStart(b)
        he.HelloAddProtocolVersion(b, version)
        return w.finish(troupe.Address(0, 0, 0), Kind.Hello, 0, 0, 0, Body.Hello, he.HelloEnd(b))


if __name__ == "__main__":
    unittest.main()
