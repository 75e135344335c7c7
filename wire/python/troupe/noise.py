"""Secure sessions, the client's side: the Noise protocol framework
(revision 34) with the pattern IK and the suite 25519_ChaChaPoly_BLAKE2b,
framed on TCP as wire/README.md ("Secure sessions") says, the same session
as the C++ NoiseTransport (wire/noise/).

    IK:
      <- s
      ...
      -> e, es, s, ss
      <- e, ee, se

The primitives are libsodium's through PyNaCl (Debian: python3-nacl):
X25519 is crypto_scalarmult, the cipher is the IETF ChaCha20-Poly1305 AEAD.
BLAKE2b is the standard library's hashlib, and HMAC its hmac module; HKDF is
the spec's construction from that HMAC. Nothing here is a primitive of its
own.

The client imports this module only for a secure session, so a plain client
runs without PyNaCl. I/O-free: bytes in, bytes out.
"""

from __future__ import annotations

import hashlib
import hmac
from typing import NamedTuple

try:
    from nacl import bindings as _nacl
    from nacl import exceptions as _nacl_errors
    from nacl import utils as _nacl_utils
except ImportError as _missing:  # pragma: no cover - depends on the machine
    raise ImportError("secure sessions need PyNaCl (Debian: apt-get install python3-nacl)") from _missing

#: The Noise protocol name: pattern, DH, cipher, hash.
PROTOCOL_NAME = b"Noise_IK_25519_ChaChaPoly_BLAKE2b"
#: Bound into every handshake: a peer of another protocol or version fails it.
PROLOGUE = b"troupe secure session 1"

#: X25519 and ChaCha20-Poly1305 keys, bytes.
KEY_BYTES = 32
#: BLAKE2b-512 output (the spec's HASHLEN), bytes.
HASH_BYTES = 64
#: The Poly1305 tag after every encrypted payload, bytes.
TAG_BYTES = 16
#: The largest Noise message, tag included, bytes.
MAX_MESSAGE_BYTES = 65535
#: Plaintext in one transport message, at most, bytes.
MAX_PLAIN_BYTES = MAX_MESSAGE_BYTES - TAG_BYTES
#: The u16 big-endian length before every Noise message on TCP, bytes.
LENGTH_BYTES = 2
#: Handshake payload a peer may send, at most, bytes (empty in this version).
MAX_HANDSHAKE_PAYLOAD_BYTES = 256
#: Message 1 with an empty payload: e, the encrypted s and the payload's tag.
MESSAGE1_BYTES = KEY_BYTES + (KEY_BYTES + TAG_BYTES) + TAG_BYTES
#: Message 2 with an empty payload: e and the payload's tag.
MESSAGE2_BYTES = KEY_BYTES + TAG_BYTES

# The spec keeps the last nonce (2^64 - 1) for rekeying: no message uses it.
_NONCE_LIMIT = 2**64 - 1


class SecureSessionError(Exception):
    """A secure session failed: a handshake or transport message that does not
    authenticate or is malformed. The session is over; nothing resyncs."""


class KeyPair(NamedTuple):
    """An X25519 key pair (32 bytes each)."""
    secret: bytes
    public: bytes


def keypair_from_secret(secret: bytes) -> KeyPair:
    """The key pair of `secret` (X25519 clamps it itself)."""
    return KeyPair(bytes(secret), _nacl.crypto_scalarmult_base(bytes(secret)))


def generate_keypair() -> KeyPair:
    """A fresh key pair from libsodium's system random source."""
    return keypair_from_secret(_nacl_utils.random(KEY_BYTES))


def _hash(*parts: bytes) -> bytes:
    h = hashlib.blake2b(digest_size=HASH_BYTES)
    for p in parts:
        h.update(p)
    return h.digest()


def _hmac(key: bytes, *parts: bytes) -> bytes:
    # hashlib's BLAKE2b has the 128-byte block the spec's HMAC pads to.
    return hmac.new(key, b"".join(parts), hashlib.blake2b).digest()


def hkdf(chaining_key: bytes, ikm: bytes, outputs: int) -> tuple[bytes, ...]:
    """The spec's HKDF (section 4.3): 2 or 3 outputs of HASH_BYTES each."""
    temp_key = _hmac(chaining_key, ikm)
    out = [_hmac(temp_key, b"\x01")]
    for i in range(2, outputs + 1):
        out.append(_hmac(temp_key, out[-1], bytes([i])))
    return tuple(out)


def _nonce(n: int) -> bytes:
    # ChaChaPoly's 96-bit nonce: 4 zero bytes, then the counter as a u64
    # little-endian.
    return b"\x00\x00\x00\x00" + n.to_bytes(8, "little")


class CipherState:
    """A key and its counter nonce. Without a key, "encryption" is the
    identity (the handshake before its first DH)."""

    def __init__(self, key: bytes | None = None):
        self.key = key
        #: The next message's nonce: messages so far in this direction.
        self.nonce = 0

    def encrypt_with_ad(self, ad: bytes, plain: bytes) -> bytes:
        if self.key is None:
            return bytes(plain)
        if self.nonce >= _NONCE_LIMIT:
            raise SecureSessionError("nonce space used up: the session must be renewed")
        out = _nacl.crypto_aead_chacha20poly1305_ietf_encrypt(bytes(plain), bytes(ad), _nonce(self.nonce), self.key)
        self.nonce += 1
        return out

    def decrypt_with_ad(self, ad: bytes, cipher: bytes) -> bytes | None:
        """The plaintext, or None when the tag does not verify (the nonce then
        stays where it was)."""
        if self.key is None:
            return bytes(cipher)
        if self.nonce >= _NONCE_LIMIT or len(cipher) < TAG_BYTES:
            return None
        try:
            out = _nacl.crypto_aead_chacha20poly1305_ietf_decrypt(bytes(cipher), bytes(ad), _nonce(self.nonce),
                                                                  self.key)
        except _nacl_errors.CryptoError:
            return None
        self.nonce += 1
        return out


class SymmetricState:
    """The chaining key, the handshake hash and the handshake's CipherState
    (the spec's section 5.2)."""

    def __init__(self, protocol_name: bytes):
        if len(protocol_name) <= HASH_BYTES:
            self.h = protocol_name.ljust(HASH_BYTES, b"\x00")
        else:
            self.h = _hash(protocol_name)
        self.ck = self.h
        self.cs = CipherState()

    def mix_key(self, input_key_material: bytes) -> None:
        self.ck, temp_k = hkdf(self.ck, input_key_material, 2)
        # HASHLEN 64: the cipher key is the first 32 bytes.
        self.cs = CipherState(temp_k[:KEY_BYTES])

    def mix_hash(self, data: bytes) -> None:
        self.h = _hash(self.h, data)

    def encrypt_and_hash(self, plain: bytes) -> bytes:
        cipher = self.cs.encrypt_with_ad(self.h, plain)
        self.mix_hash(cipher)
        return cipher

    def decrypt_and_hash(self, cipher: bytes) -> bytes | None:
        plain = self.cs.decrypt_with_ad(self.h, cipher)
        if plain is not None:
            self.mix_hash(cipher)
        return plain

    def split(self) -> tuple[CipherState, CipherState]:
        """(initiator to responder, responder to initiator)."""
        k1, k2 = hkdf(self.ck, b"", 2)
        return CipherState(k1[:KEY_BYTES]), CipherState(k2[:KEY_BYTES])


def _dh(secret: bytes, public: bytes) -> bytes:
    try:
        return _nacl.crypto_scalarmult(secret, public)
    except _nacl_errors.CryptoError:
        # libsodium refuses a public key of small order (an all-zero result):
        # a peer sending one would fix the shared secret.
        raise SecureSessionError("the peer's key is not a valid X25519 public key (small order)") from None


class InitiatorIK:
    """The IK handshake as its initiator: the client, which knows the
    responder's (the node's) static public key beforehand. `ephemeral`
    replaces the random ephemeral key (test vectors only)."""

    def __init__(self, local: KeyPair, remote_static: bytes, prologue: bytes = PROLOGUE,
                 ephemeral: KeyPair | None = None):
        self.s = local
        self.rs = bytes(remote_static)
        self.e = ephemeral
        self.step = 0  # messages done: 0, 1 or 2
        self.symmetric = SymmetricState(PROTOCOL_NAME)
        self.symmetric.mix_hash(prologue)
        # The pre-message "<- s": the responder's static key, known to both.
        self.symmetric.mix_hash(self.rs)

    @property
    def complete(self) -> bool:
        return self.step == 2

    @property
    def handshake_hash(self) -> bytes:
        return self.symmetric.h

    def write_message(self, payload: bytes = b"") -> bytes:
        """Message 1: -> e, es, s, ss, then the encrypted payload."""
        if self.step != 0:
            raise SecureSessionError("handshake message written out of turn")
        if self.e is None:
            self.e = generate_keypair()
        sym = self.symmetric
        sym.mix_hash(self.e.public)
        sym.mix_key(_dh(self.e.secret, self.rs))
        out = self.e.public + sym.encrypt_and_hash(self.s.public)
        sym.mix_key(_dh(self.s.secret, self.rs))
        out += sym.encrypt_and_hash(payload)
        if len(out) > MAX_MESSAGE_BYTES:
            raise SecureSessionError("handshake payload too large for one Noise message")
        self.step = 1
        return out

    def read_message(self, message: bytes) -> bytes:
        """Message 2: <- e, ee, se, then the encrypted payload, returned."""
        if self.step != 1:
            raise SecureSessionError("handshake message received out of turn")
        if len(message) < MESSAGE2_BYTES:
            raise SecureSessionError(f"handshake message 2 is {len(message)} bytes, shorter than the "
                                     f"{MESSAGE2_BYTES} it needs")
        sym = self.symmetric
        re = bytes(message[:KEY_BYTES])
        sym.mix_hash(re)
        sym.mix_key(_dh(self.e.secret, re))
        sym.mix_key(_dh(self.s.secret, re))
        payload = sym.decrypt_and_hash(bytes(message[KEY_BYTES:]))
        if payload is None:
            raise SecureSessionError("handshake message 2 does not authenticate: the node does not hold the private "
                                     "key of the public key we know for it (its key changed, or someone else "
                                     "answers)")
        self.step = 2
        return payload

    def split(self) -> tuple[CipherState, CipherState]:
        """After complete: (send, receive) for the initiator."""
        return self.symmetric.split()


class SecureSession:
    """One secure session over a byte stream, the client's side: begin() gives
    message 1; inbound() takes whatever the socket gave and returns the frame
    stream's bytes it carried; seal() turns frame bytes into transport
    messages. Every Noise message travels after its length as a u16
    big-endian; once anything fails, the session stays failed."""

    def __init__(self, identity: KeyPair, node_key: bytes, prologue: bytes = PROLOGUE,
                 ephemeral: KeyPair | None = None):
        """`ephemeral` replaces the random ephemeral key (test vectors only)."""
        self.identity, self.node_key, self.prologue = identity, bytes(node_key), prologue
        self._ephemeral = ephemeral
        self.handshake: InitiatorIK | None = None
        self._send: CipherState | None = None
        self._receive: CipherState | None = None
        self._in = bytearray()
        self._failure = ""

    @property
    def ready(self) -> bool:
        """The handshake is done: frames may flow."""
        return self._send is not None

    @property
    def messages_in(self) -> int:
        """Transport messages opened so far."""
        return self._receive.nonce if self._receive else 0

    @property
    def messages_out(self) -> int:
        """Transport messages sealed so far."""
        return self._send.nonce if self._send else 0

    def begin(self) -> bytes:
        """Starts (or restarts) the session: message 1, length first."""
        self.handshake = InitiatorIK(self.identity, self.node_key, self.prologue, self._ephemeral)
        self._send = self._receive = None
        self._in.clear()
        self._failure = ""
        return _framed(self.handshake.write_message())

    def inbound(self, data: bytes) -> bytes:
        """The plaintext the bytes `data` completed (b"" during the handshake or
        while a message is partial). Raises SecureSessionError when a message
        is malformed or does not authenticate."""
        if self.handshake is None:
            raise SecureSessionError("secure session used before begin()")
        if self._failure:
            raise SecureSessionError(self._failure)
        self._in += data
        plain = bytearray()
        at = 0
        try:
            while len(self._in) - at >= LENGTH_BYTES:
                n = int.from_bytes(self._in[at:at + LENGTH_BYTES], "big")
                if not self.ready:
                    self._check_handshake_length(n)
                if len(self._in) - at - LENGTH_BYTES < n:
                    break
                message = bytes(self._in[at + LENGTH_BYTES:at + LENGTH_BYTES + n])
                at += LENGTH_BYTES + n
                if not self.ready:
                    # Payloads are empty in this version; one from a later
                    # version is ignored.
                    self.handshake.read_message(message)
                    self._send, self._receive = self.handshake.split()
                else:
                    plain += self._open(message)
        except SecureSessionError as e:
            self._failure = str(e)
            self._in = bytearray()
            raise
        del self._in[:at]
        return bytes(plain)

    def seal(self, frames: bytes) -> bytes:
        """The transport messages carrying `frames`, each with its length: a
        run over MAX_PLAIN_BYTES spans several (the receiver reassembles)."""
        if not self.ready or self._failure:
            raise SecureSessionError(self._failure or "secure session not ready: the handshake is not done")
        out = bytearray()
        view = memoryview(frames)
        for at in range(0, len(view), MAX_PLAIN_BYTES):
            out += _framed(self._send.encrypt_with_ad(b"", view[at:at + MAX_PLAIN_BYTES]))
        return bytes(out)

    def _check_handshake_length(self, n: int) -> None:
        # Refused at once, so a plain node's frame length (a u32 little-endian)
        # is told from message 2 by its first two bytes.
        if not MESSAGE2_BYTES <= n <= MESSAGE2_BYTES + MAX_HANDSHAKE_PAYLOAD_BYTES:
            raise SecureSessionError(f"the node did not answer with a secure handshake ({n} bytes announced, not "
                                     f"{MESSAGE2_BYTES} to {MESSAGE2_BYTES + MAX_HANDSHAKE_PAYLOAD_BYTES}): "
                                     "an insecure node?")

    def _open(self, message: bytes) -> bytes:
        if len(message) < TAG_BYTES:
            raise SecureSessionError(f"transport message of {len(message)} bytes, shorter than its {TAG_BYTES}-byte "
                                     "tag")
        plain = self._receive.decrypt_with_ad(b"", message)
        if plain is None:
            raise SecureSessionError(f"transport message {self._receive.nonce} does not authenticate (altered, "
                                     "replayed, reordered or a message dropped): session ended")
        return plain


def _framed(message: bytes) -> bytes:
    return len(message).to_bytes(LENGTH_BYTES, "big") + message
