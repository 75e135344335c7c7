"""A session of troupe-sim recorded with `troupe record` and served again
by `troupe play`: the Python client finds the devices under the robot's
name and sees every recorded sample, values and sender timestamps alike.
The log is read here with a reader written from wire/record/README.md
alone (header, then length, CRC-32, receive time and frame per record), so
the documented format is checked too."""

import os
import struct
import subprocess
import tempfile
import time
import unittest
import zlib

import helpers
import troupe
from troupe.wire.Kind import Kind
from troupe.wire.Position2dState import Position2dState
from troupe.wire.RangerScan import RangerScan

TROUPE = os.path.join(helpers.BINARY_DIR, "bin", "troupe")
MAGIC = b"\x89TROUPE\n"


def read_log(path: str) -> list[troupe.Message]:
    """The verified messages of a complete log, in file order."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != MAGIC:
        raise AssertionError("not a troupe log")
    version, header_size = struct.unpack_from("<HH", data, 8)
    if version != 1:
        raise AssertionError(f"version {version}")
    verifier = troupe.Verifier()
    out, at = [], header_size
    while at < len(data):
        n, crc = struct.unpack_from("<II", data, at)
        if at + 16 + n > len(data):
            raise AssertionError(f"byte {at}: truncated")
        if zlib.crc32(data[at + 8:at + 16 + n]) != crc:
            raise AssertionError(f"byte {at}: checksum mismatch")
        out.append(troupe.decode(data[at + 16:at + 16 + n], verifier))
        at += 16 + n
    return out


def sample(msg: troupe.Message) -> tuple:
    """What a client reads of one Data message: the device, the sender's
    time (us) and the body's values."""
    h = msg.header
    values: tuple = ()
    p = msg.body_as(Position2dState)
    if p is not None:
        values = (p.Pose().X(), p.Pose().Y(), p.Pose().A(), p.Vel().X(), p.Vel().Y(), p.Vel().A(), p.Stall())
    r = msg.body_as(RangerScan)
    if r is not None:
        values = (r.Scale(), r.MinAngle(), r.AngularRes(), r.MaxRange(),
                  tuple(r.Ranges(i) for i in range(r.RangesLength())))
    return (h.addr, h.time_us, values)


def by_device(samples: list[tuple]) -> dict:
    """Each device's samples in order (devices due at the same moment may
    interleave differently on the way)."""
    out: dict = {}
    for s in samples:
        out.setdefault(s[0], []).append(s)
    return out


class RecordAndPlay(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.log = os.path.join(self.dir.name, "sim.trl")

    def tearDown(self):
        self.dir.cleanup()

    def troupe(self, *args: str) -> subprocess.CompletedProcess:
        return subprocess.run([TROUPE, *args], capture_output=True, text=True, timeout=120)

    def test_a_replayed_simulator_session_reads_as_recorded(self):
        with helpers.SimProcess(helpers.ROOM_WORLD, "--seed", "2") as sim:
            host = f"127.0.0.1:{sim.port}"
            cmd = self.troupe("cmd", host, "r0/position2d:0", "vel", "0.3", "0", "0.4")
            self.assertEqual(cmd.returncode, 0, cmd.stderr)
            rec = self.troupe("record", host, "r0/position2d:0", "r0/ranger:0", "-o", self.log, "--count", "20")
            self.assertEqual(rec.returncode, 0, rec.stderr)
        messages = read_log(self.log)
        kinds = [m.header.kind for m in messages]
        self.assertEqual(kinds[:2], [Kind.Hello, Kind.DeviceList])
        recorded = by_device([sample(m) for m in messages if m.header.kind == Kind.Data])
        self.assertEqual(sum(len(v) for v in recorded.values()), 20)
        self.assertEqual(len(recorded), 2)
        for samples in recorded.values():
            self.assertNotEqual(samples[0][2], samples[-1][2], "the robot was turning: its data changed")

        port = helpers.free_port()
        player = helpers.NodeProcess([TROUPE, "play", self.log, "--port", str(port), "--wait"], port)
        with player:
            client = troupe.Client("127.0.0.1", port, name="replay-reader")
            self.assertTrue(client.connect(), client.error)
            self.assertEqual(sorted((d.text(), d.driver) for d in client.device_list()),
                             [("r0/position2d:0", "troupe-sim (replay)"), ("r0/ranger:0", "troupe-sim (replay)")])
            seen = []
            client.add_data_handler(lambda msg: seen.append(sample(msg)))
            base = troupe.Position2dProxy(client, addr=client.resolve("r0/position2d:0"))
            laser = troupe.RangerProxy(client, addr=client.resolve("r0/ranger:0"))
            self.assertTrue(base.is_open and laser.is_open, client.error)
            deadline = time.monotonic() + 60
            while player.proc.poll() is None and time.monotonic() < deadline:
                client.spin_once(0.1)
            client.spin_for(0.2)
            self.assertEqual(player.proc.poll(), 0, "troupe play ends by itself after the last frame")
            client.shutdown()
        self.assertEqual(by_device(seen), recorded)
        # The proxies hold the last recorded sample of each device.
        last_pose = recorded[base.address][-1][2]
        self.assertAlmostEqual(base.x, last_pose[0], places=5)
        self.assertEqual(len(laser.ranges), len(recorded[laser.address][-1][2][4]))


if __name__ == "__main__":
    unittest.main()
