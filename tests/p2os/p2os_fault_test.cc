// Faults on the line and in the robot, each with the p2os driver in a real
// node beside a kinematic driver: the driver resyncs or reports, the node
// never stops serving the kinematic base, and odometry stays the robot's.
// The loop runs everything in one thread, so a driver that blocked would
// stall the robot too and fail these tests by their deadlines.
#include "tests/device_harness/raw_port.h"
#include "tests/p2os/p2os_fixture.h"

namespace troupe::testing {
namespace {

class P2osFaults : public P2osNode {
 protected:
  // Drives at 0.3 m/s for `seconds` with whatever faults are set, then
  // stops. Both bases must have gone on publishing meanwhile.
  void drive_through_faults(double seconds) {
    uint32_t other = client_.count(kOther), base = client_.count(kBase);
    client_.send_vel(kBase, 0.3f, 0);
    loop_.run_for(seconds);
    EXPECT_GT(client_.count(kOther), other + 5) << "the kinematic base stopped being served";
    EXPECT_GT(client_.count(kBase), base + 5) << "the Pioneer stopped publishing";
    client_.send_vel(kBase, 0, 0);
  }
  void clean_line() {
    robot_->faults().rates = {};
    robot_->inbound_faults().rates = {};
  }
};

TEST_F(P2osFaults, FlippedBits) {
  start();
  connect();
  robot_->faults().rates.bit_flip = 0.01;  // about one SIP in three hit
  drive_through_faults(3.0);
  clean_line();
  EXPECT_GE(robot_->faults().counts().flipped, 5u);
  // Bad SIPs fail their checksum and are dropped; the next good one carries
  // the robot's counters, so no motion is lost.
  EXPECT_TRUE(settles_at_robot_pose(0.002));
}

TEST_F(P2osFaults, DroppedBytes) {
  start();
  connect();
  robot_->faults().rates.byte_drop = 0.01;
  drive_through_faults(3.0);
  clean_line();
  EXPECT_GE(robot_->faults().counts().dropped, 5u);
  EXPECT_TRUE(settles_at_robot_pose(0.002));
}

TEST_F(P2osFaults, TornPackets) {
  start();
  connect();
  robot_->faults().rates.tear = 0.2;
  drive_through_faults(3.0);
  clean_line();
  EXPECT_GT(robot_->faults().counts().torn, 3u);
  EXPECT_TRUE(settles_at_robot_pose(0.002));
}

TEST_F(P2osFaults, BurstsOfGarbage) {
  start();
  connect();
  uint32_t other = client_.count(kOther);
  client_.send_vel(kBase, 0.3f, 0);
  for (int i = 0; i < 5; ++i) {
    robot_->inject_noise(1500);
    loop_.run_for(0.3);
  }
  client_.send_vel(kBase, 0, 0);
  EXPECT_GT(client_.count(kOther), other + 5);
  EXPECT_TRUE(settles_at_robot_pose(0.002));
  EXPECT_TRUE(connected());
}

TEST_F(P2osFaults, LostCommandsAreRepairedByTheResend) {
  start();
  connect();
  // Every byte to the robot lost while the command goes out...
  robot_->inbound_faults().rates.byte_drop = 1.0;
  client_.send_vel(kBase, 0.3f, 0);
  loop_.run_for(0.1);
  EXPECT_EQ(robot_->target_left_mps(), 0);
  // ...and the line restored: the driver's next keep-alive is the velocity.
  robot_->inbound_faults().rates = {};
  ASSERT_TRUE(loop_.run_until([&] { return std::fabs(robot_->target_left_mps() - 0.3) < 1e-9; }, 5));
  // A noisy line to the robot: stopping still gets through.
  robot_->inbound_faults().rates.bit_flip = 0.02;
  robot_->inbound_faults().rates.byte_drop = 0.02;
  client_.send_vel(kBase, 0, 0);
  ASSERT_TRUE(loop_.run_until([&] { return robot_->target_left_mps() == 0 && robot_->left_mps() == 0; }, 10));
}

TEST_F(P2osFaults, ThePortVanishesAndReturns) {
  start();
  connect();
  client_.send_vel(kBase, 0.3f, 0);
  ASSERT_TRUE(loop_.run_until([&] { return robot_->pose().x > 0.2; }, 10));
  client_.send_vel(kBase, 0, 0);
  ASSERT_TRUE(settles_at_robot_pose(0.002));

  ::testing::internal::CaptureStderr();
  robot_->vanish();
  ASSERT_TRUE(loop_.run_until([&] { return reports_stall(); }, 5)) << "the loss was not reported";
  uint32_t other = client_.count(kOther);
  loop_.run_for(1.5);  // gone a while: the driver retries with backoff
  EXPECT_GT(client_.count(kOther), other + 10) << "the kinematic base stopped being served";
  std::string error;
  ASSERT_TRUE(robot_->reappear(error)) << error;
  // The robot kept its session open meanwhile and streams SIPs into the
  // handshake: the driver must CLOSE it and start over.
  ASSERT_TRUE(loop_.run_until([&] { return connected(); }, 15)) << "no reconnect";
  std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(log.find("the device hung up"), std::string::npos) << log;

  client_.send_vel(kBase, 0.3f, 0);
  ASSERT_TRUE(loop_.run_until([&] { return robot_->pose().x > 0.5; }, 10));
  client_.send_vel(kBase, 0, 0);
  EXPECT_TRUE(settles_at_robot_pose(0.002));
}

TEST_F(P2osFaults, TheRobotFallsSilent) {
  start();
  connect();
  uint32_t other = client_.count(kOther);
  robot_->set_mute(true);
  ASSERT_TRUE(loop_.run_until([&] { return reports_stall(); }, 5));
  loop_.run_for(0.5);
  robot_->set_mute(false);
  ASSERT_TRUE(loop_.run_until([&] { return connected(); }, 15));
  EXPECT_GT(client_.count(kOther), other + 10);
}

TEST_F(P2osFaults, OdometryCarriesOnAcrossARobotRestart) {
  start();
  connect();
  client_.send_vel(kBase, 0.3f, 0);
  ASSERT_TRUE(loop_.run_until([&] { return robot_->pose().x > 0.3; }, 10));
  client_.send_vel(kBase, 0, 0);
  ASSERT_TRUE(settles_at_robot_pose(0.002));
  double before = pose().x();
  robot_->power_cycle();  // counters back to zero, session closed
  ASSERT_TRUE(loop_.run_until([&] { return reports_stall(); }, 5));
  ASSERT_TRUE(loop_.run_until([&] { return connected(); }, 15));
  EXPECT_NEAR(pose().x(), before, 0.002);  // no jump
  client_.send_vel(kBase, 0.3f, 0);
  ASSERT_TRUE(loop_.run_until([&] { return robot_->pose().x > 0.3; }, 10));
  client_.send_vel(kBase, 0, 0);
  ASSERT_TRUE(loop_.run_until([&] { return robot_->left_mps() == 0; }, 10));
  loop_.run_for(0.3);
  EXPECT_NEAR(pose().x() - before, robot_->pose().x, 0.002);
}

TEST_F(P2osFaults, ASessionLeftOpenByAnEarlierClient) {
  emulators::PioneerEmulator::Config config;
  robot_ = std::make_unique<emulators::PioneerEmulator>(config);
  std::string error;
  ASSERT_TRUE(robot_->open(dir_.file("pioneer"), error)) << error;
  loop_.add([this](uint64_t now) { robot_->step(now); });
  {
    // An earlier client opened a session and died without CLOSE.
    RawPort earlier(robot_->path(), B9600);
    ASSERT_TRUE(earlier.ok());
    for (auto c : {drivers::p2os::Command::Sync0, drivers::p2os::Command::Sync1,
                   drivers::p2os::Command::Sync2, drivers::p2os::Command::Open}) {
      ASSERT_TRUE(earlier.write(drivers::p2os::command(c).view()));
      loop_.run_for(0.05);
    }
  }
  ASSERT_EQ(robot_->session(), emulators::PioneerEmulator::Session::Open);
  start_node();
  connect();
}

}  // namespace
}  // namespace troupe::testing
