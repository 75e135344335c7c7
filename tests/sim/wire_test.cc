// troupe-sim over the wire: the runner serves a world on a real TCP port in
// its own thread; the C++ client drives a robot, reads its ranger and uses
// simulation:0 (pause, step, poses, reset).
#include <gtest/gtest.h>

#include <cmath>
#include <thread>

#include "tests/sim/served_world.h"
#include "wire/client/proxies.h"

namespace troupe::sim {
namespace {

// A 10 x 6 m room (inner faces at x = +-5, y = +-3), r0 at the centre with
// a laser, r1 elsewhere.
const char* kWorld = R"(
resolution 0.02
interval_sim 100
model ( name "room" size [10.4 6.4] color "gray30"
  block ( points 4 point[0] [0 0] point[1] [10.4 0] point[2] [10.4 0.2] point[3] [0 0.2] )
  block ( points 4 point[0] [0 6.2] point[1] [10.4 6.2] point[2] [10.4 6.4] point[3] [0 6.4] )
  block ( points 4 point[0] [0 0] point[1] [0.2 0] point[2] [0.2 6.4] point[3] [0 6.4] )
  block ( points 4 point[0] [10.2 0] point[1] [10.4 0] point[2] [10.4 6.4] point[3] [10.2 6.4] ) )
define bot position ( size [0.4 0.4] localization "gps" localization_origin [0 0 0 0]
  acceleration_bounds [-10 10 -10 10 0 0 -900 900] )
bot ( name "r0" pose [0 0 0 0] ranger ( sensor ( range [0 8] fov 180 samples 181 ) ) )
bot ( name "r1" pose [-3 2 0 90] )
)";

class WireTest : public test::ServedWorld {
 protected:
  WireTest() : ServedWorld(kWorld) {}
};

TEST_F(WireTest, ListsEveryRobotsDevicesAndTheSimulation) {
  client::Client c("127.0.0.1", runner_.port());
  ASSERT_TRUE(c.connect()) << c.error();
  std::vector<client::DeviceEntry> devices;
  ASSERT_TRUE(c.device_list(devices));
  std::vector<std::string> names;
  for (const auto& d : devices) names.push_back(d.text());
  EXPECT_EQ(names,
            (std::vector<std::string>{"r0/position2d:0", "r0/ranger:0", "r1/position2d:0", "simulation:0", "map:0"}));
  wire::Address a;
  ASSERT_TRUE(c.resolve("r1/position2d:0", a));
  EXPECT_EQ(a.robot(), 1);
}

TEST_F(WireTest, AClientDrivesARobotAndItsRangerSeesTheWall) {
  client::Client c("127.0.0.1", runner_.port());
  ASSERT_TRUE(c.connect()) << c.error();
  client::Position2dProxy base(c, 0, 0);
  client::RangerProxy laser(c, 0, 0);
  client::SimulationProxy sim(c);
  ASSERT_TRUE(base.is_open() && laser.is_open() && sim.is_open());

  ASSERT_TRUE(sim.step(1));
  ASSERT_TRUE(c.sync());
  ASSERT_EQ(laser.count(), 181u);
  EXPECT_NEAR(laser.bearing(0), -kPi / 2, 1e-4);
  EXPECT_NEAR(laser.range(90), 5.0, 0.02);   // ahead: x = 5
  EXPECT_NEAR(laser.range(180), 3.0, 0.02);  // left: y = 3
  EXPECT_NEAR(base.x(), 0.0, 1e-6);

  ASSERT_TRUE(base.set_velocity(0.5, 0, 0));
  ASSERT_TRUE(sim.step(10));  // 1 s
  ASSERT_TRUE(c.sync());
  EXPECT_NEAR(base.x(), 0.5, 1e-4);
  EXPECT_NEAR(base.velocity().x, 0.5, 1e-4);
  EXPECT_NEAR(laser.range(90), 4.5, 0.02);
  EXPECT_EQ(sim.sim_time_us(), 1100000u);
  // Data carries simulated time.
  EXPECT_EQ(base.time_us(), 1100000u);

  // Driven into the wall it stops and says so.
  ASSERT_TRUE(base.set_velocity(1.0, 0, 0));
  ASSERT_TRUE(sim.step(60));
  ASSERT_TRUE(c.sync());
  EXPECT_TRUE(base.stall());
  EXPECT_LE(base.x() + 0.2, 5.0 + 1e-4);  // touching at most (floats on the wire)
  EXPECT_GT(base.x() + 0.2, 4.8);
}

TEST_F(WireTest, SimulationPosesAndReset) {
  client::Client c("127.0.0.1", runner_.port());
  ASSERT_TRUE(c.connect()) << c.error();
  client::SimulationProxy sim(c);
  client::Pose2 p;
  ASSERT_TRUE(sim.get_pose("r1", p));
  EXPECT_NEAR(p.x, -3, 1e-6);
  EXPECT_NEAR(p.a, kPi / 2, 1e-6);
  ASSERT_TRUE(sim.set_pose("r1", {1.5, -1, 0.25f}));
  ASSERT_TRUE(sim.get_pose("r1", p));
  EXPECT_NEAR(p.x, 1.5, 1e-6);
  ASSERT_TRUE(sim.get_pose("room", p));  // a static model has a pose too
  EXPECT_FALSE(sim.set_pose("room", {0, 0, 0}));
  EXPECT_NE(c.error().find("static"), std::string::npos) << c.error();
  EXPECT_FALSE(sim.get_pose("nobody", p));
  EXPECT_NE(c.error().find("no model named 'nobody'"), std::string::npos) << c.error();

  ASSERT_TRUE(sim.step(5));
  ASSERT_TRUE(sim.reset());
  ASSERT_TRUE(sim.get_pose("r1", p));
  EXPECT_NEAR(p.x, -3, 1e-6);
  EXPECT_EQ(sim.sim_time_us(), 0u);
  // Running again, real time advances the clock by itself.
  ASSERT_TRUE(sim.set_speed(0));
  ASSERT_TRUE(sim.resume());
  c.spin_for(200);
  ASSERT_TRUE(sim.pause());
  EXPECT_GT(sim.sim_time_us(), 0u);
}

// The simulator publishes only what someone reads, so the node's stored
// sample of a device nobody read is from when it was last read: a new
// reader must get the current one first (it got t=0.1 s, x=0 while the
// robot stood at 2.19 m).
TEST_F(WireTest, ANewReaderFirstGetsTheCurrentSampleNotAStaleOne) {
  {
    client::Client first("127.0.0.1", runner_.port());
    ASSERT_TRUE(first.connect()) << first.error();
    client::Position2dProxy base(first, 0, 0);
    client::RangerProxy laser(first, 0, 0);
    client::SimulationProxy sim(first);
    ASSERT_TRUE(sim.step(1));
    ASSERT_TRUE(first.sync());
    ASSERT_EQ(base.time_us(), 100000u);
    ASSERT_NEAR(base.x(), 0.0, 1e-6);
    ASSERT_NEAR(laser.range(90), 5.0, 0.02);  // the wall ahead
  }  // gone: r0's odometry and laser have no reader now

  client::Client c("127.0.0.1", runner_.port());
  ASSERT_TRUE(c.connect()) << c.error();
  client::SimulationProxy sim(c);
  ASSERT_TRUE(sim.set_pose("r0", {2.19f, 0.5f, 0.25f}));  // its odometry follows (gps)
  ASSERT_TRUE(sim.step(5));
  const uint64_t now_us = sim.sim_time_us();
  ASSERT_EQ(now_us, 600000u);

  client::Position2dProxy base(c, 0, 0);
  ASSERT_TRUE(base.is_open()) << c.error();
  ASSERT_TRUE(c.sync());  // paused: no step publishes anything after the Open
  ASSERT_EQ(base.samples(), 1u);
  EXPECT_EQ(base.time_us(), now_us);
  EXPECT_NEAR(base.x(), 2.19, 1e-5);
  EXPECT_NEAR(base.y(), 0.5, 1e-5);
  EXPECT_NEAR(base.a(), 0.25, 1e-5);

  // A sensor nobody reads is not computed: its first sample is the scan the
  // simulator computes for the new reader, from where the robot stands.
  // It comes after the Open's Ack, when the server loop has seen the new
  // reader: wait for it (the bound only ends a hang).
  client::RangerProxy laser(c, 0, 0);
  ASSERT_TRUE(laser.is_open()) << c.error();
  for (int i = 0; i < 2000 && laser.samples() == 0; ++i) c.spin_once(10);
  ASSERT_EQ(laser.samples(), 1u);
  EXPECT_EQ(laser.time_us(), now_us);
  ASSERT_EQ(laser.count(), 181u);
  EXPECT_NEAR(laser.range(90), (5.0 - 2.19) / std::cos(0.25), 0.02);  // the wall x = 5, seen 0.25 rad off
}

TEST_F(WireTest, BadRequestsAreRefusedAndTheServerGoesOn) {
  client::Client c("127.0.0.1", runner_.port());
  ASSERT_TRUE(c.connect()) << c.error();
  client::SimulationProxy sim(c);
  EXPECT_FALSE(sim.set_speed(-2));
  EXPECT_FALSE(sim.step(2000000));
  client::RangerProxy laser(c, 0, 0);
  wire::Pose3d pose;
  std::vector<wire::Pose3d> elements;
  ASSERT_TRUE(laser.geometry(pose, elements));
  EXPECT_EQ(elements.size(), 1u);
  // A second client sees the same world.
  client::Client c2("127.0.0.1", runner_.port());
  ASSERT_TRUE(c2.connect()) << c2.error();
  client::SimulationProxy sim2(c2);
  client::Pose2 p;
  EXPECT_TRUE(sim2.get_pose("r0", p));
  EXPECT_TRUE(sim.step(1));
}

TEST(WirePortPerRobot, ASingleRobotClientAttachesToItsRobotsPort) {
  troupe::test::TempDir dir;
  SimOptions o;
  o.world = dir.write("w.world", kWorld);
  o.port = 0;
  o.paused = true;
  o.port_per_robot = true;
  Runner runner;
  world::Diagnostics d;
  std::string error;
  ASSERT_TRUE(runner.init(o, d, error)) << d.str() << error;
  ASSERT_NE(runner.robot_port(1), 0);
  std::thread sim([&] { runner.run(); });
  {
    // A client that knows nothing of robots: position2d:0 is r1 on its port.
    client::Client c("127.0.0.1", runner.robot_port(1));
    ASSERT_TRUE(c.connect()) << c.error();
    std::vector<client::DeviceEntry> devices;
    ASSERT_TRUE(c.device_list(devices));
    ASSERT_EQ(devices.size(), 1u);
    EXPECT_EQ(devices[0].text(), "r1/position2d:0");
    EXPECT_EQ(devices[0].addr.robot(), 0);
    client::Position2dProxy base(c);
    ASSERT_TRUE(base.set_velocity(0.4, 0, 0));
    ASSERT_TRUE(c.sync());
    client::Client main("127.0.0.1", runner.port());
    ASSERT_TRUE(main.connect()) << main.error();
    client::SimulationProxy control(main);
    ASSERT_TRUE(control.step(5));
    client::Pose2 p;
    ASSERT_TRUE(control.get_pose("r1", p));
    EXPECT_NEAR(p.x, -3, 1e-5);  // r1 faces +y: it moved along y
    EXPECT_NEAR(p.y, 2.2, 1e-4);
    ASSERT_TRUE(control.get_pose("r0", p));
    EXPECT_NEAR(p.x, 0, 1e-6);
  }
  runner.request_stop();
  sim.join();
}

}  // namespace
}  // namespace troupe::sim
