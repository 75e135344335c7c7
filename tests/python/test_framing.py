"""FrameReader: frames split across reads, coalesced in one read, and length
prefixes over the limit refused before any buffer grows for them."""

import random
import struct
import unittest

import troupe
from troupe.wire.Kind import Kind


def frames(n: int) -> list[bytes]:
    w = troupe.MessageWriter()
    return [w.finish(troupe.Address(0, 1, i % 3), Kind.Data, 1, i, 1000 + i) for i in range(n)]


class FrameReaderTest(unittest.TestCase):
    def test_frames_split_byte_by_byte_come_out_whole(self):
        sent = frames(5)
        reader = troupe.FrameReader()
        got = []
        for byte in b"".join(sent):
            reader.feed(bytes([byte]))
            while (f := reader.next()) is not None:
                got.append(f)
        self.assertEqual(got, sent)
        self.assertEqual(reader.pending_bytes(), 0)

    def test_coalesced_frames_in_one_read(self):
        sent = frames(50)
        reader = troupe.FrameReader()
        reader.feed(b"".join(sent))
        got = []
        while (f := reader.next()) is not None:
            got.append(f)
        self.assertEqual(got, sent)

    def test_random_read_sizes(self):
        sent = frames(200)
        stream = b"".join(sent)
        rng = random.Random(7)
        reader = troupe.FrameReader()
        got, at = [], 0
        while at < len(stream):
            n = rng.randint(1, 300)
            reader.feed(stream[at:at + n])
            at += n
            while (f := reader.next()) is not None:
                got.append(f)
        self.assertEqual(got, sent)

    def test_truncated_stream_keeps_the_partial_frame_pending(self):
        one = frames(1)[0]
        reader = troupe.FrameReader()
        reader.feed(one[:-3])
        self.assertIsNone(reader.next())
        self.assertEqual(reader.pending_bytes(), len(one) - 3)

    def test_oversized_prefix_is_refused_before_allocating(self):
        reader = troupe.FrameReader(max_frame_bytes=1024)
        reader.feed(struct.pack("<I", 0x7FFFFFF0) + b"xy")
        self.assertIsNone(reader.next())
        self.assertTrue(reader.too_large)
        self.assertEqual(reader.announced_bytes, 0x7FFFFFF0)
        # Nothing is kept for it, and the broken stream is not read further.
        self.assertEqual(reader.pending_bytes(), 0)
        reader.feed(b"z" * 4096)
        self.assertEqual(reader.pending_bytes(), 0)
        self.assertIsNone(reader.next())

    def test_a_frame_exactly_at_the_limit_passes(self):
        reader = troupe.FrameReader(max_frame_bytes=64)
        reader.feed(struct.pack("<I", 60) + bytes(60))
        self.assertEqual(len(reader.next()), 64)
        reader.feed(struct.pack("<I", 61))
        self.assertIsNone(reader.next())
        self.assertTrue(reader.too_large)


if __name__ == "__main__":
    unittest.main()
