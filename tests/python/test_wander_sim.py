"""examples/python/wander.py driving the robot of examples/worlds/room.world
in the real troupe-sim, in real time: the test watches the simulator's
ground truth (simulation:0 getpose), the robot's odometry and stall flag,
and its laser, through a second client."""

import math
import subprocess
import sys
import time
import unittest

import helpers
import troupe

# examples/worlds/room.world, which says the same in its header.
ROOM_HALF = 4.0  # inner wall faces at x, y = +-4 m
PILLARS = [(1.5, 1.5, 0.5), (-1.5, -1.0, 0.5)]  # centre x, y and half size, m
ROBOT_HALF_LENGTH = 0.25  # m; the robot is 0.5 x 0.4 m
ROBOT_HALF_DIAGONAL = math.hypot(0.25, 0.2)  # 0.32 m: no part of it reaches further from its centre


def clearance(x: float, y: float) -> float:
    """Distance from a point to the nearest wall or pillar face, m."""
    nearest = ROOM_HALF - max(abs(x), abs(y))
    for px, py, half in PILLARS:
        dx, dy = max(abs(x - px) - half, 0.0), max(abs(y - py) - half, 0.0)
        nearest = min(nearest, math.hypot(dx, dy))
    return nearest


class Watcher:
    """A second client on the simulator: the robot's odometry (every sample,
    stall counted), its laser, and ground truth polled through simulation:0."""

    def __init__(self, port: int):
        self.client = troupe.Client("127.0.0.1", port, name="watcher")
        if not self.client.connect():
            raise RuntimeError(self.client.error)
        base, laser = self.client.resolve("r0/position2d:0"), self.client.resolve("r0/ranger:0")
        if base is None or laser is None:
            raise RuntimeError(self.client.error)
        self.base = troupe.Position2dProxy(self.client, addr=base)
        self.laser = troupe.RangerProxy(self.client, addr=laser)
        self.sim = troupe.SimulationProxy(self.client)
        if not (self.base.is_open and self.laser.is_open and self.sim.is_open):
            raise RuntimeError(self.client.error)
        self.stalled_samples = 0
        self.nearest_laser = math.inf
        self.client.add_data_handler(self._on_data)

    def _on_data(self, msg: troupe.Message) -> None:
        # Handlers run after the proxies took the sample in.
        if msg.header.addr == self.base.address and self.base.stall:
            self.stalled_samples += 1
        elif msg.header.addr == self.laser.address and self.laser.ranges:
            self.nearest_laser = min(self.nearest_laser, min(self.laser.ranges))

    def truth(self) -> troupe.Pose2:
        pose = self.sim.get_pose("r0")
        if pose is None:
            raise AssertionError(f"simulation:0 getpose r0: {self.client.error}")
        return pose


class InTheSimulator(unittest.TestCase):
    def test_wander_explores_the_room_and_never_touches_anything(self):
        with helpers.SimProcess(helpers.ROOM_WORLD, "--seed", "5") as sim:
            watcher = Watcher(sim.port)
            start = watcher.truth()
            proc = subprocess.Popen([sys.executable, helpers.WANDER, f"127.0.0.1:{sim.port}", "--duration", "25",
                                     "--seed", "4"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
            path, farthest, closest, last = 0.0, 0.0, math.inf, start
            poses = 0
            while proc.poll() is None:
                watcher.client.spin_once(0.2)
                pose = watcher.truth()
                poses += 1
                path += math.hypot(pose.x - last.x, pose.y - last.y)
                farthest = max(farthest, math.hypot(pose.x - start.x, pose.y - start.y))
                closest = min(closest, clearance(pose.x, pose.y))
                last = pose
            out, err = proc.communicate()
            self.assertEqual(proc.returncode, 0, err.decode())
            self.assertIn("scans", err.decode())
            print(f"\nground truth: path {path:.2f} m, farthest from the start {farthest:.2f} m, nearest surface "
                  f"{closest:.2f} m; laser nearest {watcher.nearest_laser:.2f} m", file=sys.stderr)
            self.assertGreater(poses, 20, "too few ground-truth poses to judge the run")
            # 25 s at up to 0.4 m/s: it keeps moving instead of turning on the
            # spot, and gets well away from where it started.
            self.assertGreater(path, 4.0, f"ground-truth path {path:.2f} m")
            self.assertGreater(farthest, 2.0, f"never got more than {farthest:.2f} m from the start")
            # Its centre stays further from every surface than any part of
            # the robot reaches, so it never touched one; the simulator would
            # have refused the move and reported a stall.
            self.assertGreater(closest, ROBOT_HALF_DIAGONAL, f"came within {closest:.2f} m of a surface")
            self.assertEqual(watcher.stalled_samples, 0, "the robot stalled against something")
            self.assertGreater(watcher.nearest_laser, ROBOT_HALF_DIAGONAL,
                               f"its laser saw a surface {watcher.nearest_laser:.2f} m away")
            # wander stops the base when it ends; stopped, the gps odometry
            # (localization_origin at the world's origin) is the ground truth.
            deadline = time.monotonic() + 10
            while time.monotonic() < deadline and (watcher.base.velocity.x != 0.0 or watcher.base.velocity.a != 0.0):
                watcher.client.spin_once(0.1)
            self.assertEqual((watcher.base.velocity.x, watcher.base.velocity.a), (0.0, 0.0))
            watcher.client.spin_for(0.3)
            truth = watcher.truth()
            self.assertAlmostEqual(watcher.base.x, truth.x, delta=0.01)
            self.assertAlmostEqual(watcher.base.y, truth.y, delta=0.01)
            watcher.client.shutdown()

    def test_a_robot_driven_blindly_into_a_wall_stalls_there(self):
        # The other side of the assertions above: without avoidance the
        # simulator stops the robot at the wall, reports the stall, and its
        # laser sees the wall at the robot's nose.
        with helpers.SimProcess(helpers.ROOM_WORLD) as sim:
            watcher = Watcher(sim.port)
            self.assertTrue(watcher.sim.set_pose("r0", troupe.Pose2(2.5, 3.0, 0.0)), watcher.client.error)
            self.assertTrue(watcher.base.set_velocity(0.5, 0.0, 0.0), watcher.client.error)
            deadline = time.monotonic() + 60
            while watcher.stalled_samples == 0 and time.monotonic() < deadline:
                watcher.client.spin_once(0.1)
            self.assertGreater(watcher.stalled_samples, 0, "the robot never stalled")
            truth = watcher.truth()
            watcher.base.set_velocity(0.0, 0.0, 0.0)
            # Stopped with its nose at the east wall (x = 4 m), within a few cells.
            self.assertAlmostEqual(truth.x, ROOM_HALF - ROBOT_HALF_LENGTH, delta=0.06)
            self.assertAlmostEqual(truth.y, 3.0, delta=0.01)
            self.assertLess(clearance(truth.x, truth.y), ROBOT_HALF_DIAGONAL)
            watcher.client.spin_for(0.3)
            ahead = watcher.laser.ranges[len(watcher.laser.ranges) // 2]
            self.assertAlmostEqual(ahead, ROBOT_HALF_LENGTH, delta=0.06)
            watcher.client.shutdown()


if __name__ == "__main__":
    unittest.main()
