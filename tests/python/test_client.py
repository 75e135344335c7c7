"""The Python client against the real troupe-node (the kinematic example,
position2d:0 at 10 Hz) over TCP: session, proxies, requests, delivery modes,
errors, and reconnecting when the node comes back."""

import math
import socket
import unittest

import helpers
import troupe
from troupe.wire import Position2dSetOdom
from troupe.wire.Body import Body
from troupe.wire.Delivery import Delivery
from troupe.wire.ErrorCode import ErrorCode
from troupe.wire.Kind import Kind
from troupe.wire.Pose2d import CreatePose2d
from troupe.wire.Position2dReqSub import Position2dReqSub


spin_until = helpers.spin_until


class WithNode(unittest.TestCase):
    def setUp(self):
        self.port = helpers.free_port()
        self.node = helpers.kinematic_node(self.port).start()
        self.client = troupe.Client("127.0.0.1", self.port, name="py-test")
        self.assertTrue(self.client.connect(), self.client.error)

    def tearDown(self):
        self.client.shutdown()
        self.assertEqual(self.node.stop(), 0, "troupe-node did not stop cleanly")


class Session(WithNode):
    def test_hello_names_the_node_and_sync_measures_the_clock(self):
        self.assertTrue(self.client.connected)
        self.assertEqual(self.client.node_name, "kinematic-demo")
        self.assertEqual(self.client.connections, 1)
        self.assertTrue(self.client.sync())
        # Node and client read the same monotonic clock on this machine.
        self.assertLess(abs(self.client.clock_offset_us), 1_000_000)

    def test_device_list_and_resolve(self):
        devices = self.client.device_list()
        self.assertEqual([d.text() for d in devices], ["position2d:0"])
        self.assertEqual(devices[0].driver, "kinematic")
        self.assertEqual(self.client.resolve("position2d:0"), troupe.Address(0, 1, 0))
        self.assertEqual(self.client.resolve("7/ranger:2"), troupe.Address(7, 2, 2))
        self.assertIsNone(self.client.resolve("r3/position2d:0"))
        self.assertIn("no robot named 'r3'", self.client.error)
        with self.assertRaisesRegex(ValueError, "unknown interface 'laser'"):
            self.client.resolve("laser:0")

    def test_data_handlers_see_every_message(self):
        seen = []
        hid = self.client.add_data_handler(seen.append)
        self.assertTrue(self.client.open(troupe.Address(0, 1, 0)))
        self.assertTrue(spin_until(self.client, lambda: len(seen) >= 3))
        self.assertTrue(all(m.header.kind == Kind.Data for m in seen))
        self.assertEqual([m.header.seq for m in seen[1:3]], [seen[0].header.seq + 1, seen[0].header.seq + 2])
        self.client.remove_data_handler(hid)
        count = len(seen)
        self.client.spin_for(0.3)
        self.assertEqual(len(seen), count)


class Position2d(WithNode):
    def test_data_arrives_and_velocity_moves_the_base(self):
        base = troupe.Position2dProxy(self.client)
        self.assertTrue(base.is_open, self.client.error)
        self.assertTrue(spin_until(self.client, lambda: base.samples >= 2))
        self.assertTrue(base.fresh())
        self.assertFalse(base.fresh())
        self.assertAlmostEqual(base.x, 0.0)
        self.assertTrue(base.set_velocity(0.5, 0.0, 0.0))
        # The example accelerates at 0.5 m/s^2: it moves within a second or so.
        self.assertTrue(spin_until(self.client, lambda: base.x > 0.05), base.pose)
        self.assertAlmostEqual(base.y, 0.0, places=5)
        self.assertGreater(base.velocity.x, 0.0)
        self.assertFalse(base.stall)
        self.assertIsNone(base.covariance)
        self.assertIsNone(base.fault)

    def test_requests_reply_with_their_bodies(self):
        base = troupe.Position2dProxy(self.client)
        size, offset = base.geometry()
        self.assertAlmostEqual(size.x, 0.5)  # the kinematic driver's default footprint
        self.assertAlmostEqual(size.y, 0.4)
        self.assertEqual(offset, troupe.Pose3())
        self.assertTrue(base.set_odometry(1.0, 2.0, 0.5))
        self.assertTrue(spin_until(self.client, lambda: abs(base.y - 2.0) < 1e-3))
        self.assertAlmostEqual(base.a, 0.5, places=5)
        self.assertTrue(base.reset_odometry())
        self.assertTrue(spin_until(self.client, lambda: abs(base.x) < 1e-3 and abs(base.y) < 1e-3))

    def test_go_to_reaches_the_goal(self):
        base = troupe.Position2dProxy(self.client)
        self.assertTrue(base.go_to(0.5, 0.0, 0.0))
        self.assertTrue(spin_until(self.client, lambda: math.hypot(base.x - 0.5, base.y) < 0.05, 20), base.pose)

    def test_motor_power_off_holds_the_base(self):
        base = troupe.Position2dProxy(self.client)
        self.assertTrue(base.set_motor_power(False))
        base.set_velocity(0.5, 0, 0)
        self.assertTrue(self.client.sync())
        self.client.spin_for(0.5)
        self.assertAlmostEqual(base.x, 0.0)

    def test_non_finite_values_are_refused(self):
        base = troupe.Position2dProxy(self.client)
        with self.assertRaisesRegex(ValueError, "vx is nan"):
            base.set_velocity(math.nan, 0, 0)
        with self.assertRaisesRegex(ValueError, "max_vel.a is inf"):
            base.go_to(1, 0, 0, troupe.Pose2(0.1, 0, math.inf))
        with self.assertRaisesRegex(ValueError, "y is -inf"):
            base.set_odometry(0, -math.inf, 0)
        # A message built by hand past the proxies meets the node's check.
        b = self.client.begin()
        Position2dSetOdom.Position2dSetOdomStart(b)
        Position2dSetOdom.Position2dSetOdomAddPose(b, CreatePose2d(b, math.nan, 0, 0))
        reply = self.client.request(base.address, Position2dReqSub.SetOdometry, Body.Position2dSetOdom,
                                    Position2dSetOdom.Position2dSetOdomEnd(b))
        self.assertEqual(reply.status, troupe.Reply.NACK)
        self.assertEqual(reply.code, ErrorCode.BadValue)
        self.assertIn("pose.x", reply.text)
        self.assertTrue(spin_until(self.client, lambda: base.samples >= 2))
        self.assertTrue(math.isfinite(base.x))

    def test_a_request_the_device_does_not_know_is_nacked(self):
        reply = self.client.request(troupe.Address(0, 1, 0), 77)
        self.assertFalse(reply.ok)
        self.assertEqual(reply.status, troupe.Reply.NACK)
        self.assertEqual(reply.code, ErrorCode.Unsupported)
        self.assertEqual(self.client.request(troupe.Address(0, 1, 0), Position2dReqSub.ResetOdometry).status,
                         troupe.Reply.ACK)

    def test_pull_delivery_sends_one_sample_per_pull(self):
        addr = troupe.Address(0, 1, 0)
        seen = []
        self.client.add_data_handler(seen.append)
        self.assertTrue(self.client.open(addr, delivery=Delivery.Pull))
        self.client.spin_for(0.4)  # 4 samples published; none pushed
        self.assertEqual(seen, [])
        self.assertTrue(self.client.pull(addr))
        self.assertEqual(len(seen), 1)
        self.assertTrue(self.client.pull(addr))
        self.assertEqual(len(seen), 2)

    def test_udp_data(self):
        client = troupe.Client("127.0.0.1", self.port, udp_data=True)
        self.assertTrue(client.connect(), client.error)
        base = troupe.Position2dProxy(client)
        self.assertTrue(spin_until(client, lambda: base.samples >= 3))
        client.shutdown()


class Errors(WithNode):
    def test_opening_a_device_the_node_lacks(self):
        ranger = troupe.RangerProxy(self.client)
        self.assertFalse(ranger.is_open)
        self.assertIn("no such device", self.client.error)
        self.assertTrue(self.client.connected)

    def test_a_bad_frame_we_send_gets_an_error_and_the_client_reconnects(self):
        base = troupe.Position2dProxy(self.client)
        self.client.send_frame(b"\x08\x00\x00\x00garbage!")
        self.assertTrue(spin_until(self.client, lambda: not self.client.connected))
        self.assertTrue(self.client.error.startswith("node closed the connection:"), self.client.error)
        self.assertTrue(spin_until(self.client, lambda: self.client.connections == 2))
        before = base.samples
        self.assertTrue(spin_until(self.client, lambda: base.samples > before + 2))

    def test_no_node(self):
        refused = troupe.Client("127.0.0.1", helpers.free_port(), reconnect=False)
        self.assertFalse(refused.connect(1.0))
        self.assertIn("Connection refused", refused.error)
        nowhere = troupe.Client("no-such-host.invalid", 6665, reconnect=False)
        self.assertFalse(nowhere.connect(1.0))
        self.assertIn("cannot resolve host 'no-such-host.invalid'", nowhere.error)
        self.assertFalse(nowhere.command(troupe.Address(0, 1, 0), 1))
        self.assertEqual(nowhere.request(troupe.Address(0, 1, 0), 1).status, troupe.Reply.DISCONNECTED)


def debian_localhost(host: str, port: int) -> list:
    """localhost as a standard Debian 12 resolves it: ::1 first, then 127.0.0.1."""
    assert host == "localhost"
    return [(socket.AF_INET6, ("::1", port, 0, 0)), (socket.AF_INET, ("127.0.0.1", port))]


class Localhost(unittest.TestCase):
    def test_v6_first_still_reaches_a_node_on_v4_only(self):
        port = helpers.free_port()
        with helpers.kinematic_node(port):  # listens on 127.0.0.1 only
            client = troupe.Client("localhost", port, reconnect=False, resolver=debian_localhost)
            self.assertEqual(client.state, "idle")
            self.assertTrue(client.connect(3.0), client.error)
            self.assertEqual(client.state, "up")
            self.assertEqual([d.text() for d in client.device_list()], ["position2d:0"])
            client.shutdown()
            self.assertEqual(client.state, "idle")

    def test_nothing_listening_is_one_clear_error(self):
        port = helpers.free_port()
        client = troupe.Client("localhost", port, resolver=debian_localhost)
        self.assertFalse(client.connect(3.0))
        self.assertEqual(client.error, f"cannot connect to localhost:{port}: Connection refused")
        self.assertEqual(client.state, "waiting")
        client.shutdown()


class Reconnect(unittest.TestCase):
    def test_proxies_resume_when_the_node_comes_back(self):
        port = helpers.free_port()
        node = helpers.kinematic_node(port).start()
        client = troupe.Client("127.0.0.1", port, reconnect_min=0.05, reconnect_max=0.2)
        try:
            self.assertTrue(client.connect())
            base = troupe.Position2dProxy(client)
            self.assertTrue(spin_until(client, lambda: base.samples >= 1))
            node.stop()
            self.assertTrue(spin_until(client, lambda: not client.connected))
            self.assertFalse(base.set_velocity(0.1, 0, 0))
            client.spin_for(0.5)  # a few failed attempts while nothing listens
            node = helpers.kinematic_node(port).start()
            self.assertTrue(spin_until(client, lambda: client.connected))
            self.assertEqual(client.connections, 2)
            # The device was opened again without the caller doing anything.
            seq = base.seq
            self.assertTrue(spin_until(client, lambda: base.samples >= 3 and base.seq != seq))
            self.assertTrue(base.set_velocity(0.5, 0, 0))
            self.assertTrue(spin_until(client, lambda: base.x > 0.02))
        finally:
            client.shutdown()
            node.stop()


if __name__ == "__main__":
    unittest.main()
