"""examples/python/wander.py: its controller on made-up scans, and the
program itself driving the kinematic base of room_node (a real Node over
TCP) around a 6 m room with a pillar, watched by a second client."""

import math
import os
import random
import subprocess
import sys
import time
import unittest

import helpers
import troupe

sys.path.insert(0, os.path.join(helpers.SOURCE_DIR, "examples", "python"))
import wander  # noqa: E402

BEARINGS = [-math.pi / 2 + i * math.pi / 180 for i in range(181)]
ROOM_HALF = 3.0  # room_node's default: walls at x, y = +-3 m
PILLAR = (1.5, 0.0, 0.3)  # centre x, y and half size, m


def scan(obstacle_bearing: float | None = None, distance: float = 0.0, clear: float = 5.0) -> list[float]:
    """A scan of open space with one obstacle 20 degrees wide."""
    return [distance if obstacle_bearing is not None and abs(b - obstacle_bearing) < math.radians(10) else clear
            for b in BEARINGS]


def clearance(x: float, y: float) -> float:
    """Distance from a point to the nearest wall or pillar face, m."""
    walls = ROOM_HALF - max(abs(x), abs(y))
    px, py, half = PILLAR
    dx, dy = max(abs(x - px) - half, 0.0), max(abs(y - py) - half, 0.0)
    return min(walls, math.hypot(dx, dy))


class Controller(unittest.TestCase):
    def setUp(self):
        self.w = wander.Wander(wander.WanderParams(), random.Random(3))

    def test_open_space_drives_at_cruise_speed_with_a_bounded_drift(self):
        v, a = self.w.step(scan(), BEARINGS, 0.0)
        self.assertEqual(v, wander.WanderParams.speed)
        self.assertLessEqual(abs(a), wander.WanderParams.max_drift)

    def test_an_obstacle_close_ahead_left_turns_right_on_the_spot(self):
        v, a = self.w.step(scan(math.radians(15), 0.4), BEARINGS, 0.0)
        self.assertEqual(v, 0.0)
        self.assertLess(a, 0.0)

    def test_an_obstacle_close_ahead_right_turns_left(self):
        v, a = self.w.step(scan(math.radians(-15), 0.4), BEARINGS, 0.0)
        self.assertEqual(v, 0.0)
        self.assertGreater(a, 0.0)

    def test_an_obstacle_at_middle_distance_slows_and_bends_away(self):
        v, a = self.w.step(scan(math.radians(20), 1.0), BEARINGS, 0.0)
        self.assertGreater(v, 0.0)
        self.assertLess(v, wander.WanderParams.speed)
        self.assertLess(a, 0.0)

    def test_it_keeps_turning_one_way_until_the_front_is_clear(self):
        _, first = self.w.step(scan(math.radians(5), 0.4), BEARINGS, 0.0)
        # The obstacle now looks slightly on the other side: no dithering.
        _, second = self.w.step(scan(math.radians(-5), 0.4), BEARINGS, 0.1)
        self.assertEqual(math.copysign(1, first), math.copysign(1, second))

    def test_obstacles_behind_the_front_sector_do_not_stop_it(self):
        v, _ = self.w.step(scan(math.radians(85), 0.3), BEARINGS, 0.0)
        self.assertGreater(v, 0.0)

    def test_same_seed_same_drift(self):
        a = wander.Wander(wander.WanderParams(), random.Random(11))
        b = wander.Wander(wander.WanderParams(), random.Random(11))
        for t in range(20):
            self.assertEqual(a.step(scan(), BEARINGS, t * 0.5), b.step(scan(), BEARINGS, t * 0.5))


class InTheRoom(unittest.TestCase):
    def test_wander_explores_the_room_without_touching_anything(self):
        port = helpers.free_port()
        with helpers.room_node(port):
            env = dict(os.environ)
            proc = subprocess.Popen([sys.executable, helpers.WANDER, f"127.0.0.1:{port}", "--duration", "25",
                                     "--seed", "4"], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
            watcher = troupe.Client("127.0.0.1", port, name="watcher")
            self.assertTrue(watcher.connect(), watcher.error)
            base = troupe.Position2dProxy(watcher)
            path, closest, last = 0.0, math.inf, None
            while proc.poll() is None:
                watcher.spin_once(0.1)
                if not base.fresh():
                    continue
                x, y = base.x, base.y
                if last is not None:
                    path += math.hypot(x - last[0], y - last[1])
                closest = min(closest, clearance(x, y))
                last = (x, y)
            out, err = proc.communicate()
            self.assertEqual(proc.returncode, 0, err.decode())
            self.assertIn("scans", err.decode())
            # Without avoidance a 0.4 m/s robot meets a wall within 8 s; in 25 s
            # it covers several metres and its centre stays off every surface
            # by more than its half-diagonal (0.32 m for the 0.5 x 0.4 m base).
            self.assertGreater(path, 4.0, f"path {path:.2f} m")
            self.assertGreater(closest, 0.33, f"came within {closest:.2f} m of a surface")
            # wander stops the base when it ends.
            watcher.spin_for(0.5)
            self.assertAlmostEqual(base.velocity.x, 0.0, places=3)
            watcher.shutdown()


if __name__ == "__main__":
    unittest.main()
