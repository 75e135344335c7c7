// The p2os driver in a real node, against the Pioneer emulator on a pty:
// connecting, driving, odometry, sonar, power, bumpers, requests, and the
// errors a bad config or an unknown robot give.
#include <cmath>

#include "tests/p2os/p2os_fixture.h"

namespace troupe::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST_F(P2osNode, FindsTheRobotByProbingBauds) {
  emulators::PioneerEmulator::Config robot;
  robot.baud = 38400;  // the driver tries 9600 first
  start(robot);
  connect();
  EXPECT_EQ(robot_->session(), emulators::PioneerEmulator::Session::Open);
  EXPECT_TRUE(robot_->motors_enabled());
  EXPECT_TRUE(robot_->sonar_enabled());
}

TEST_F(P2osNode, DrivesForwardAndReportsOdometry) {
  start();
  connect();
  client_.send_vel(kBase, 0.3f, 0);
  ASSERT_TRUE(loop_.run_until([&] { return robot_->pose().x > 0.6; }, 10));
  // VEL2 carries 0.3 m/s exactly (15 units of 20 mm/s per wheel).
  EXPECT_NEAR(robot_->target_left_mps(), 0.3, 1e-9);
  EXPECT_NEAR(robot_->target_right_mps(), 0.3, 1e-9);
  const wire::Position2dState* s = position_state(client_, kBase);
  ASSERT_NE(s, nullptr);
  EXPECT_NEAR(s->vel()->x(), 0.3, 1e-3);
  client_.send_vel(kBase, 0, 0);
  ASSERT_TRUE(settles_at_robot_pose(0.002));
  EXPECT_NEAR(pose().y(), 0, 0.002);
  EXPECT_NEAR(pose().a(), 0, 0.002);
}

TEST_F(P2osNode, TurnsAndReportsHeading) {
  start();
  connect();
  client_.send_vel(kBase, 0, 0.8f);
  ASSERT_TRUE(loop_.run_until([&] { return robot_->pose().a > 2.0; }, 10));
  client_.send_vel(kBase, 0, 0);
  ASSERT_TRUE(loop_.run_until(
      [&] {
        double robot_a = std::remainder(robot_->pose().a, 2 * kPi);
        return robot_->left_mps() == 0 && std::fabs(std::remainder(pose().a() - robot_a, 2 * kPi)) < 0.003;
      },
      10));
}

TEST_F(P2osNode, VelAndRvelWhenVel2IsOff) {
  start({}, R"("use_vel2": false)");
  connect();
  client_.send_vel(kBase, 0.25f, 0.5f);
  ASSERT_TRUE(loop_.run_until([&] { return robot_->left_mps() > 0.1; }, 10));
  // 0.5 rad/s is sent as 29 deg/s: each wheel differs by w / DiffConv.
  double turn = 29 * kPi / 180 / 0.0056 / 1000;
  EXPECT_NEAR(robot_->target_left_mps(), 0.25 - turn, 1e-9);
  EXPECT_NEAR(robot_->target_right_mps(), 0.25 + turn, 1e-9);
}

TEST_F(P2osNode, KeepAlivesHoldTheRobotPastItsWatchdog) {
  start();
  connect();
  client_.send_vel(kBase, 0.2f, 0);  // once, then nothing from the client
  loop_.run_for(3.0);                // longer than the robot's 2 s watchdog
  EXPECT_FALSE(robot_->watchdog_tripped());
  EXPECT_NEAR(robot_->left_mps(), 0.2, 1e-9);
}

TEST_F(P2osNode, CommandTimeoutStopsTheRobot) {
  start({}, R"("command_timeout_ms": 500)");
  connect();
  client_.send_vel(kBase, 0.2f, 0);
  ASSERT_TRUE(loop_.run_until([&] { return robot_->left_mps() > 0.1; }, 10));
  ASSERT_TRUE(loop_.run_until([&] { return robot_->target_left_mps() == 0; }, 10));
  EXPECT_FALSE(robot_->watchdog_tripped());  // the driver stopped it, not the robot
}

class KnownSurroundings : public emulators::PioneerWorld {
 public:
  void sense(const emulators::PioneerPose&, const drivers::p2os::RobotParams& robot,
             emulators::PioneerSenses& s) override {
    for (size_t i = 0; i < robot.sonar_count; ++i) s.sonar_m[i] = 0.4f + 0.1f * float(i);
    s.battery_v = 11.8f;
    s.front_bumpers = 0x05;
    s.rear_bumpers = 0x02;
  }
  bool move(double l, double r, double track, double dt, emulators::PioneerPose& p) override {
    if (blocked) return true;
    return PioneerWorld::move(l, r, track, dt, p);
  }
  bool blocked = false;
};

TEST_F(P2osNode, PublishesTheSonarRingWithItsGeometry) {
  KnownSurroundings world;
  start({}, "", &world);
  connect();
  ASSERT_TRUE(loop_.run_until([&] { return client_.count(kSonar) > 0; }, 10));
  const wire::RangerScan* scan = client_.last(kSonar)->body_as_RangerScan();
  ASSERT_NE(scan, nullptr);
  ASSERT_EQ(scan->ranges()->size(), 16u);
  for (uint32_t i = 0; i < 16; ++i) EXPECT_EQ(scan->ranges()->Get(i), 400 + 100 * i) << "sonar " << i;
  EXPECT_FLOAT_EQ(scan->scale(), 0.001f);
  EXPECT_FLOAT_EQ(scan->max_range(), 5.0f);

  uint32_t seq = client_.request(kSonar, uint8_t(wire::RangerReqSub::Geometry));
  ASSERT_TRUE(loop_.run_until([&] { return client_.reply(seq) != nullptr; }, 5));
  const wire::RangerGeometry* g = client_.reply(seq)->body_as_RangerGeometry();
  ASSERT_NE(g, nullptr);
  ASSERT_EQ(g->elements()->size(), 16u);
  EXPECT_FLOAT_EQ(g->elements()->Get(0)->x(), 0.069f);
  EXPECT_FLOAT_EQ(g->elements()->Get(0)->y(), 0.136f);
  EXPECT_NEAR(g->elements()->Get(0)->yaw(), kPi / 2, 1e-6);
  EXPECT_NEAR(g->elements()->Get(11)->yaw(), -170 * kPi / 180, 1e-6);
}

TEST_F(P2osNode, SonarPowerRequestSwitchesTheRing) {
  start();
  connect();
  uint32_t seq = client_.request_switch(kSonar, uint8_t(wire::RangerReqSub::Power), false);
  ASSERT_TRUE(loop_.run_until([&] { return client_.reply(seq) != nullptr; }, 5));
  EXPECT_EQ(client_.reply(seq)->header()->kind(), wire::Kind::Ack);
  ASSERT_TRUE(loop_.run_until([&] { return !robot_->sonar_enabled(); }, 5));
}

TEST_F(P2osNode, PublishesBatteryAndBumpers) {
  KnownSurroundings world;
  start({}, "", &world);
  connect();
  ASSERT_TRUE(loop_.run_until([&] { return client_.count(kPower) > 0 && client_.count(kBumper) > 0; }, 10));
  const wire::PowerState* power = client_.last(kPower)->body_as_PowerState();
  ASSERT_NE(power, nullptr);
  ASSERT_TRUE(power->volts().has_value());
  EXPECT_FLOAT_EQ(*power->volts(), 11.8f);
  const wire::BumperState* bumpers = client_.last(kBumper)->body_as_BumperState();
  ASSERT_NE(bumpers, nullptr);
  EXPECT_EQ(bumpers->count(), 14);
  EXPECT_EQ(bumpers->pressed(), 0x05u | (0x02u << 7));  // front ring, then rear
}

TEST_F(P2osNode, ReportsAStalledBase) {
  KnownSurroundings world;
  start({}, "", &world);
  connect();
  world.blocked = true;
  client_.send_vel(kBase, 0.3f, 0);
  ASSERT_TRUE(loop_.run_until([&] { return reports_stall(); }, 10));
  world.blocked = false;
  ASSERT_TRUE(loop_.run_until([&] { return connected(); }, 10));
}

TEST_F(P2osNode, MotorPowerRequestEnablesAndDisables) {
  start();
  connect();
  uint32_t off = client_.request_switch(kBase, uint8_t(wire::Position2dReqSub::MotorPower), false);
  ASSERT_TRUE(loop_.run_until([&] { return client_.reply(off) && !robot_->motors_enabled(); }, 5));
  client_.send_vel(kBase, 0.3f, 0);
  loop_.run_for(0.5);
  EXPECT_EQ(robot_->left_mps(), 0);
  uint32_t on = client_.request_switch(kBase, uint8_t(wire::Position2dReqSub::MotorPower), true);
  ASSERT_TRUE(loop_.run_until([&] { return client_.reply(on) && robot_->motors_enabled(); }, 5));
  client_.send_vel(kBase, 0.3f, 0);
  ASSERT_TRUE(loop_.run_until([&] { return robot_->left_mps() > 0.1; }, 5));
}

TEST_F(P2osNode, ResetOdometryRestartsBothEnds) {
  start();
  connect();
  client_.send_vel(kBase, 0.4f, 0);
  ASSERT_TRUE(loop_.run_until([&] { return robot_->pose().x > 0.5; }, 10));
  client_.send_vel(kBase, 0, 0);
  ASSERT_TRUE(settles_at_robot_pose(0.002));
  uint32_t seq = client_.request(kBase, uint8_t(wire::Position2dReqSub::ResetOdometry));
  ASSERT_TRUE(loop_.run_until([&] { return client_.reply(seq) != nullptr; }, 5));
  // The robot's own counters restart (SETO) and the driver's pose with them.
  ASSERT_TRUE(loop_.run_until([&] { return std::fabs(robot_->pose().x) < 1e-9; }, 5));
  EXPECT_NEAR(pose().x(), 0, 0.002);
  client_.send_vel(kBase, 0.4f, 0);
  ASSERT_TRUE(loop_.run_until([&] { return robot_->pose().x > 0.3; }, 10));
  client_.send_vel(kBase, 0, 0);
  ASSERT_TRUE(settles_at_robot_pose(0.002));
}

TEST_F(P2osNode, GeometryIsTheRobotsFootprint) {
  start();
  connect();
  uint32_t seq = client_.request(kBase, uint8_t(wire::Position2dReqSub::Geometry));
  ASSERT_TRUE(loop_.run_until([&] { return client_.reply(seq) != nullptr; }, 5));
  const wire::Position2dGeometry* g = client_.reply(seq)->body_as_Position2dGeometry();
  ASSERT_NE(g, nullptr);
  EXPECT_FLOAT_EQ(g->size()->x(), 0.511f);
  EXPECT_FLOAT_EQ(g->size()->y(), 0.400f);
}

TEST_F(P2osNode, TheModelOptionOverridesTheRobotsSubclass) {
  emulators::PioneerEmulator::Config robot;
  robot.model = "p3dx";  // counts of 0.485 mm
  start(robot, R"("model": "p3dx")");
  connect();
  client_.send_vel(kBase, 0.3f, 0);
  ASSERT_TRUE(loop_.run_until([&] { return robot_->pose().x > 0.4; }, 10));
  client_.send_vel(kBase, 0, 0);
  ASSERT_TRUE(settles_at_robot_pose(0.002));
}

TEST_F(P2osNode, AnUnknownRobotIsReportedAndTheNodeServesOn) {
  emulators::PioneerEmulator::Config robot;
  robot.model = "p9xyz";
  ::testing::internal::CaptureStderr();
  start(robot);
  uint32_t before = 0;
  ASSERT_TRUE(loop_.run_until([&] { return (before = client_.count(kOther)) > 0 && reports_stall(); }, 10));
  loop_.run_for(1.0);
  std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(log.find("p9xyz"), std::string::npos) << log;
  EXPECT_NE(log.find("\"model\" option"), std::string::npos) << log;
  EXPECT_GT(client_.count(kOther), before + 10);  // the kinematic base is served all along
  EXPECT_FALSE(connected());
  EXPECT_NE(robot_->session(), emulators::PioneerEmulator::Session::Open);
}

TEST_F(P2osNode, BadOptionsKeepTheNodeFromStarting) {
  struct Case {
    const char* options;
    const char* error;
  } cases[] = {
      {R"("model": "p9")", "unknown robot 'p9' (known: p3dx-sh, p3dx)"},
      {R"("baud": 12345)", "option \"baud\": 12345"},
      {R"("pulse_ms": 2500)", "\"pulse_ms\" must be in [50, 1500] ms"},
      {R"("reopen_min_ms": 900, "reopen_max_ms": 100)", "\"reopen_max_ms\" at least as large"},
  };
  for (const Case& c : cases) {
    NodeUnderTest node;
    std::string error;
    EXPECT_FALSE(node.start(config(c.options), error)) << c.options;
    EXPECT_NE(error.find(c.error), std::string::npos) << error;
    EXPECT_NE(error.find("drivers[0] (p2os)"), std::string::npos) << error;
  }
  NodeUnderTest node;
  std::string error;
  std::string no_port = R"({ "drivers": [ { "driver_type": "p2os", "provides": ["position2d:0"] } ] })";
  EXPECT_FALSE(node.start(no_port, error));
  EXPECT_NE(error.find("option \"port\" is missing"), std::string::npos) << error;
  std::string wrong_device = R"({ "drivers": [ { "driver_type": "p2os", "driver": { "port": "x" },
                                  "provides": ["imu:0"] } ] })";
  EXPECT_FALSE(node.start(wrong_device, error));
  EXPECT_NE(error.find("not imu"), std::string::npos) << error;
}

TEST_F(P2osNode, AMissingPortIsRetriedUntilTheRobotAppears) {
  ::testing::internal::CaptureStderr();
  start_node();  // no robot yet
  uint32_t before = 0;
  ASSERT_TRUE(loop_.run_until([&] { return (before = client_.count(kOther)) > 0 && reports_stall(); }, 10));
  loop_.run_for(0.6);
  std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(log.find(dir_.file("pioneer") + ": No such file or directory"), std::string::npos) << log;
  robot_ = std::make_unique<emulators::PioneerEmulator>(emulators::PioneerEmulator::Config{});
  std::string error;
  ASSERT_TRUE(robot_->open(dir_.file("pioneer"), error)) << error;
  loop_.add([this](uint64_t now) { robot_->step(now); });
  connect();
  EXPECT_GT(client_.count(kOther), before);
}

}  // namespace
}  // namespace troupe::testing
