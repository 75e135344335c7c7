"""A fiducial detection's kind reaches the client's Detection: detections
with kinds keep them, those the sender gave none (or fewer) are Generic."""

import unittest

import sample_frames as S
import troupe
from troupe.wire.FiducialKind import FiducialKind


def detections(frame: bytes) -> list:
    proxy = troupe.FiducialProxy.__new__(troupe.FiducialProxy)  # no connection: only the decoding
    proxy._update(troupe.decode(frame, troupe.Verifier()))
    return proxy.fiducials


class FiducialKindTest(unittest.TestCase):
    def test_kinds_are_read_per_detection(self):
        got = detections(S.fiducials(3, [FiducialKind.Ball, FiducialKind.Goal, FiducialKind.Post]))
        self.assertEqual([d.kind for d in got], [FiducialKind.Ball, FiducialKind.Goal, FiducialKind.Post])
        self.assertEqual([d.id for d in got], [0, 1, 2])
        self.assertAlmostEqual(got[1].x, 2.0)

    def test_missing_kinds_are_generic(self):
        self.assertEqual([d.kind for d in detections(S.fiducials(2))], [FiducialKind.Generic] * 2)
        short = detections(S.fiducials(3, [FiducialKind.Robot]))
        self.assertEqual([d.kind for d in short], [FiducialKind.Robot, FiducialKind.Generic, FiducialKind.Generic])


if __name__ == "__main__":
    unittest.main()
