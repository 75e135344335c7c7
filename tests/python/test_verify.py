"""The verifier: well-formed frames pass and read back; malformed ones are
refused with VerifyError (saying what and where) and nothing else ever
escapes, including for frames a seeded fuzzer mutates at random."""

import inspect
import random
import struct
import unittest

import sample_frames as S
import troupe
from troupe.message import BODY_CODES
from troupe.wire import Body as _body_module  # noqa: F401  (the generated package is importable)
from troupe.wire.Position2dState import Position2dState
from troupe.wire.RangerScan import RangerScan

_BODY_CLASSES = {}
for _name, _code in BODY_CODES.items():
    _module = __import__(f"troupe.wire.{_name}", fromlist=[_name])
    _BODY_CLASSES[_code] = getattr(_module, _name)


def read_everything(obj) -> list:
    """Calls every generated accessor of a table, every vector element
    included; returns the values read."""
    values = []
    for name, fn in inspect.getmembers(obj, inspect.ismethod):
        if name.startswith(("Init", "GetRootAs")) or name.endswith(("AsNumpy", "IsNone")):
            continue
        params = [p for p in inspect.signature(fn).parameters.values()]
        if name.endswith("Length") and hasattr(obj, name[:-len("Length")] + "IsNone"):
            item = getattr(obj, name[:-len("Length")])
            for j in range(fn()):
                value = item(j)
                values.append(read_everything(value) if hasattr(value, "_tab") else value)
        elif not params:
            value = fn()
            values.append((name, read_everything(value) if hasattr(value, "_tab") else value))
    return values


def decode_fully(frame: bytes, verifier: troupe.Verifier) -> tuple:
    """The header and every value of the body."""
    msg = troupe.decode(frame, verifier)
    cls = _BODY_CLASSES.get(msg.body_type)
    body = msg.body_as(cls) if cls else None
    return msg.header, msg.body_type, read_everything(body) if body is not None else []


def with_prefix(body: bytes) -> bytes:
    return struct.pack("<I", len(body)) + body


class WellFormed(unittest.TestCase):
    def test_every_sample_verifies_and_reads_back(self):
        v = troupe.Verifier()
        for name, frame in S.all_samples().items():
            with self.subTest(name):
                self.assertGreater(len(decode_fully(frame, v)[2]), 0)

    def test_values_read_back(self):
        v = troupe.Verifier()
        msg = troupe.decode(S.position2d(x=1.25, seq=42), v)
        self.assertEqual(msg.header.seq, 42)
        self.assertEqual(msg.header.addr, troupe.Address(0, 1, 0))
        self.assertEqual(msg.header.time_us, 1_000_042)
        s = msg.body_as(Position2dState)
        self.assertEqual((s.Pose().X(), s.Pose().Y()), (1.25, -2.0))
        self.assertEqual(s.Fault(), b"left axis silent")
        self.assertIsNone(msg.body_as(RangerScan))

    def test_an_unknown_body_type_passes_unread(self):
        # A newer peer's body: the C++ verifier lets it through too, and the
        # node answers Nack Unsupported; readers just do not understand it.
        frame = bytearray(S.power())
        v = troupe.Verifier()
        msg = troupe.decode(bytes(frame), v)
        # Find the union type byte through the message's vtable and change it.
        root = struct.unpack_from("<I", frame, 4)[0] + 4
        vt = root - struct.unpack_from("<i", frame, root)[0]
        type_at = root + struct.unpack_from("<H", frame, vt + 6)[0]
        self.assertEqual(frame[type_at], msg.body_type)
        frame[type_at] = 250
        unknown = troupe.decode(bytes(frame), v)
        self.assertEqual(unknown.body_type, 250)
        self.assertIsNone(unknown.body_as(RangerScan))


class Malformed(unittest.TestCase):
    def setUp(self):
        self.v = troupe.Verifier()

    def refuse(self, frame: bytes, words: str, verifier=None) -> troupe.VerifyError:
        with self.assertRaises(troupe.VerifyError) as caught:
            (verifier or self.v).verify(frame)
        self.assertIn(words, str(caught.exception))
        self.assertIn("(byte ", str(caught.exception))
        return caught.exception

    def test_short_and_mismatched_lengths(self):
        self.refuse(b"\x04\x00\x00\x00", "too short")
        frame = S.ranger()
        self.refuse(frame[:-1], "does not match")
        self.refuse(frame + b"\x00", "does not match")

    def test_every_truncation_is_refused_or_loses_nothing(self):
        # The prefix is fixed up to the shorter length, so that the cut
        # reaches the structural checks. Cutting only trailing padding leaves
        # a good frame with the same content; any other cut is refused.
        for name, frame in S.all_samples().items():
            whole = decode_fully(frame, self.v)
            refused = 0
            for cut in range(8, len(frame)):
                with self.subTest(name=name, cut=cut):
                    try:
                        self.assertEqual(decode_fully(with_prefix(frame[4:cut]), self.v), whole)
                    except troupe.VerifyError:
                        refused += 1
            self.assertGreaterEqual(refused, len(frame) - 8 - 7, name)

    def test_root_offset_outside_the_frame(self):
        frame = bytearray(S.power())
        struct.pack_into("<I", frame, 4, 0xFFFFFF00)
        e = self.refuse(bytes(frame), "root offset")
        self.assertEqual(e.offset, 4)

    def test_vector_longer_than_the_frame(self):
        frame = bytearray(S.ranger(beams=10))
        v = troupe.Verifier()
        msg = troupe.decode(bytes(frame), v)
        scan = msg.body_as(RangerScan)
        o = scan._tab.Offset(4)  # ranges
        length_at = scan._tab.Vector(o) - 4
        struct.pack_into("<I", frame, length_at, 1_000_000)
        e = self.refuse(bytes(frame), "RangerScan.ranges: vector of 1000000 x 2 bytes runs past")
        self.assertEqual(e.offset, length_at)

    def test_string_without_terminator(self):
        frame = bytearray(S.position2d(fault="abc"))
        at = bytes(frame).index(b"abc")
        frame[at + 3] = ord("x")  # the NUL after "abc"
        self.refuse(bytes(frame), "Position2dState.fault: string")

    def test_vtable_outside_the_frame(self):
        frame = bytearray(S.power())
        root = struct.unpack_from("<I", frame, 4)[0] + 4
        struct.pack_into("<i", frame, root, -100000)
        self.refuse(bytes(frame), "Message: vtable outside the frame")

    def test_table_count_and_depth_limits(self):
        many = S.device_list(count=60)
        self.v.verify(many)
        self.refuse(many, "more than 50 tables", troupe.Verifier(limits=troupe.Limits(max_tables=50)))
        self.refuse(many, "nested deeper than 2", troupe.Verifier(limits=troupe.Limits(max_depth=2)))

    def test_frame_over_the_limit(self):
        self.refuse(S.ranger(beams=400), "over the limit", troupe.Verifier(limits=troupe.Limits(max_frame_bytes=512)))

    def test_random_mutations_raise_nothing_but_verify_errors(self):
        rng = random.Random(20240611)
        samples = list(S.all_samples().values())
        accepted = refused = 0
        for _ in range(6000):
            frame = bytearray(rng.choice(samples))
            for _ in range(rng.randint(1, 6)):
                at = rng.randrange(4, len(frame))
                frame[at] = rng.randrange(256) if rng.random() < 0.7 else frame[at] ^ (1 << rng.randrange(8))
            try:
                decode_fully(bytes(frame), self.v)
                accepted += 1
            except troupe.VerifyError:
                refused += 1
        # Both outcomes occur: mutations of scalar values are valid frames.
        self.assertGreater(accepted, 100)
        self.assertGreater(refused, 100)


if __name__ == "__main__":
    unittest.main()
