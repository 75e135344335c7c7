"""The Python client's Noise IK (troupe.noise) against the test vectors of
flynn/noise, an implementation nobody here wrote (Debian ships them with
golang-github-flynn-noise-dev; CMake finds the file and passes its path as
TROUPE_NOISE_VECTORS, as for tests/security/noise_test.cc). Only the
vectors of the project's protocol, Noise_IK_25519_ChaChaPoly_BLAKE2b, count.

The client is the initiator: it writes the vectors' messages 0, 2, 4, ...
and reads 1, 3, 5, ... as the responder wrote them. Then the same session
as the client runs it on TCP (troupe.noise.SecureSession: u16 big-endian
lengths, the handshake, transport messages), fed the vectors' bytes whole,
byte by byte, and tampered with."""

import os
import unittest

from troupe import noise

VECTORS = os.environ.get("TROUPE_NOISE_VECTORS", "")


def read_vectors(path: str, protocol: str) -> list[dict[str, str]]:
    """The blank-line separated blocks of "name=hex" lines of one protocol."""
    blocks, block = [], {}
    with open(path, encoding="ascii") as f:
        for line in list(f) + [""]:
            line = line.strip()
            if not line:
                if block.get("handshake") == protocol:
                    blocks.append(block)
                block = {}
            elif "=" in line:
                name, value = line.split("=", 1)
                block[name] = value
    return blocks


def messages(v: dict[str, str]) -> list[tuple[bytes, bytes]]:
    """(payload, ciphertext) of msg_0, msg_1, ... in order."""
    out = []
    while f"msg_{len(out)}_ciphertext" in v:
        n = len(out)
        out.append((bytes.fromhex(v[f"msg_{n}_payload"]), bytes.fromhex(v[f"msg_{n}_ciphertext"])))
    return out


def framed(message: bytes) -> bytes:
    return len(message).to_bytes(2, "big") + message


@unittest.skipUnless(os.path.exists(VECTORS),
                     f"no Noise test vectors at '{VECTORS}' (apt-get install golang-github-flynn-noise-dev)")
class FlynnNoiseVectors(unittest.TestCase):
    def setUp(self):
        self.vectors = read_vectors(VECTORS, noise.PROTOCOL_NAME.decode())
        # The file holds four: with and without a prologue and payloads.
        self.assertGreaterEqual(len(self.vectors), 4, f"{VECTORS} holds no {noise.PROTOCOL_NAME.decode()} vectors")

    def keys(self, v):
        initiator = noise.keypair_from_secret(bytes.fromhex(v["init_static"]))
        responder = noise.keypair_from_secret(bytes.fromhex(v["resp_static"]))
        ephemeral = noise.keypair_from_secret(bytes.fromhex(v["gen_init_ephemeral"]))
        return initiator, responder, ephemeral, bytes.fromhex(v.get("prologue", ""))

    def test_the_handshake_and_transport_give_the_vectors_bytes(self):
        for v in self.vectors:
            with self.subTest(prologue=v.get("prologue", ""), first_payload=v["msg_0_payload"]):
                initiator, responder, ephemeral, prologue = self.keys(v)
                hs = noise.InitiatorIK(initiator, responder.public, prologue, ephemeral)
                msgs = messages(v)
                self.assertGreaterEqual(len(msgs), 4)
                self.assertEqual(hs.write_message(msgs[0][0]).hex(), msgs[0][1].hex())
                self.assertEqual(hs.read_message(msgs[1][1]), msgs[1][0])
                self.assertTrue(hs.complete)
                send, receive = hs.split()
                for n, (payload, cipher) in enumerate(msgs[2:], start=2):
                    if n % 2 == 0:  # ours: initiator to responder
                        self.assertEqual(send.encrypt_with_ad(b"", payload).hex(), cipher.hex(), f"msg_{n}")
                    else:
                        self.assertEqual(receive.decrypt_with_ad(b"", cipher), payload, f"msg_{n}")

    def test_an_altered_message_2_does_not_authenticate(self):
        v = self.vectors[0]
        initiator, responder, ephemeral, prologue = self.keys(v)
        msgs = messages(v)
        for at in (0, 40, len(msgs[1][1]) - 1):  # the node's e, the payload's tag
            hs = noise.InitiatorIK(initiator, responder.public, prologue, ephemeral)
            hs.write_message(msgs[0][0])
            altered = bytearray(msgs[1][1])
            altered[at] ^= 0x01
            with self.assertRaisesRegex(noise.SecureSessionError, "does not authenticate.*its key changed"):
                hs.read_message(bytes(altered))
            self.assertFalse(hs.complete)

    def test_another_node_key_does_not_authenticate(self):
        v = self.vectors[0]
        initiator, _, ephemeral, prologue = self.keys(v)
        msgs = messages(v)
        # Message 1 addressed to another node: the real node's answer fails.
        hs = noise.InitiatorIK(initiator, noise.generate_keypair().public, prologue, ephemeral)
        self.assertNotEqual(hs.write_message(msgs[0][0]), msgs[0][1])
        with self.assertRaisesRegex(noise.SecureSessionError, "does not authenticate"):
            hs.read_message(msgs[1][1])


@unittest.skipUnless(os.path.exists(VECTORS),
                     f"no Noise test vectors at '{VECTORS}' (apt-get install golang-github-flynn-noise-dev)")
class SessionOnTheVectors(unittest.TestCase):
    """SecureSession with the vectors' keys: what goes on the TCP stream."""

    def setUp(self):
        # A vector with empty handshake payloads, as troupe's are.
        self.v = next(v for v in read_vectors(VECTORS, noise.PROTOCOL_NAME.decode())
                      if not v["msg_0_payload"] and not v["msg_1_payload"])
        self.msgs = messages(self.v)
        initiator = noise.keypair_from_secret(bytes.fromhex(self.v["init_static"]))
        responder = noise.keypair_from_secret(bytes.fromhex(self.v["resp_static"]))
        ephemeral = noise.keypair_from_secret(bytes.fromhex(self.v["gen_init_ephemeral"]))
        self.session = noise.SecureSession(initiator, responder.public, bytes.fromhex(self.v.get("prologue", "")),
                                           ephemeral)
        self.first = self.session.begin()

    def test_message_1_is_the_vectors_with_its_length_first(self):
        self.assertEqual(self.first, framed(self.msgs[0][1]))
        self.assertEqual(len(self.msgs[0][1]), noise.MESSAGE1_BYTES)
        self.assertFalse(self.session.ready)
        with self.assertRaisesRegex(noise.SecureSessionError, "not ready"):
            self.session.seal(b"too early")

    def test_the_stream_byte_by_byte_gives_the_plaintext(self):
        stream = framed(self.msgs[1][1]) + framed(self.msgs[3][1])
        plain = b"".join(self.session.inbound(stream[i:i + 1]) for i in range(len(stream)))
        self.assertEqual(plain, self.msgs[3][0])
        self.assertTrue(self.session.ready)
        self.assertEqual(self.session.seal(self.msgs[2][0]), framed(self.msgs[2][1]))
        self.assertEqual((self.session.messages_in, self.session.messages_out), (1, 1))

    def test_a_long_run_of_frames_is_split_into_messages_of_at_most_65535_bytes(self):
        self.session.inbound(framed(self.msgs[1][1]))
        run = bytes(range(256)) * 600  # 153,600 bytes: three messages
        out = self.session.seal(run)
        lengths, at = [], 0
        while at < len(out):
            n = int.from_bytes(out[at:at + 2], "big")
            lengths.append(n)
            at += 2 + n
        self.assertEqual(at, len(out))
        self.assertEqual(lengths, [65535, 65535, len(run) - 2 * noise.MAX_PLAIN_BYTES + noise.TAG_BYTES])
        self.assertEqual(self.session.messages_out, 3)

    def tampered(self, transport: bytes, error: str) -> None:
        """The node's message 2, then `transport`: the session ends with `error`
        and stays ended."""
        self.assertEqual(self.session.inbound(framed(self.msgs[1][1])), b"")
        with self.assertRaisesRegex(noise.SecureSessionError, error):
            self.session.inbound(transport)
        with self.assertRaisesRegex(noise.SecureSessionError, error):
            self.session.inbound(framed(self.msgs[3][1]))

    def test_a_replayed_transport_message_ends_the_session(self):
        good = framed(self.msgs[3][1])
        self.assertEqual(self.session.inbound(framed(self.msgs[1][1]) + good), self.msgs[3][0])
        with self.assertRaisesRegex(noise.SecureSessionError, r"transport message 1 does not authenticate"):
            self.session.inbound(good)

    def test_an_altered_transport_message_ends_the_session(self):
        altered = bytearray(self.msgs[3][1])
        altered[3] ^= 0x80
        self.tampered(framed(bytes(altered)), "transport message 0 does not authenticate")

    def test_a_truncated_transport_message_ends_the_session(self):
        self.tampered(framed(self.msgs[3][1][:-1]), "transport message 0 does not authenticate")
        self.setUp()
        self.tampered(framed(self.msgs[3][1][:10]), "transport message of 10 bytes, shorter than its 16-byte tag")

    def test_a_plain_nodes_hello_is_no_handshake(self):
        # A plain node speaks first: its Hello's u32 little-endian length.
        with self.assertRaisesRegex(noise.SecureSessionError, r"did not answer with a secure handshake \(15360 bytes "
                                    r"announced, not 48 to 304\): an insecure node\?"):
            self.session.inbound(b"\x3c\x00\x00\x00")


if __name__ == "__main__":
    unittest.main()
