// Faults on the CAN bus, injected in the ODrive emulator: for each, the
// driver stops both axes, reports stall and why on position2d, recovers when
// the axes are back, and the node goes on serving its other device (a
// kinematic base the client keeps commanding) all along.
#include <gtest/gtest.h>

#include <cmath>

#include "drivers/odrive_can/cansimple.h"
#include "tests/odrive/odrive_rig.h"

namespace troupe::testing {
namespace {

using cansimple::AxisState;
namespace axis_error = cansimple::axis_error;

bool running(OdriveRig& rig) {
  return rig.left().state() == AxisState::ClosedLoopControl &&
         rig.right().state() == AxisState::ClosedLoopControl;
}

bool recovered(OdriveRig& rig) {
  return running(rig) && !rig.base().stall && rig.base().fault.empty();
}

// Drives the base forward at 0.3 m/s until both wheels turn.
void start_driving(OdriveRig& rig) {
  ASSERT_EQ(rig.error(), "");
  ASSERT_TRUE(rig.run_until([&] { return running(rig); }, 5));
  rig.client.command_vel(OdriveRig::kBase, 0.3f, 0);
  ASSERT_TRUE(
      rig.run_until([&] { return rig.left().velocity() > 0.5f && rig.right().velocity() > 0.5f; }, 3));
}

// Waits for the driver to report the fault, then for both axes to stop: each
// is IDLE or commanded to zero (by the driver, or by its own watchdog when
// the driver's frames cannot reach it).
void expect_stopped_and_reported(OdriveRig& rig, const std::string& why) {
  ASSERT_TRUE(rig.run_until([&] { return rig.base().stall; }, 3)) << "no stall reported";
  EXPECT_NE(rig.base().fault.find(why), std::string::npos) << "fault text: " << rig.base().fault;
  auto stopped = [](const emulators::odrive::Axis& axis) {
    return axis.state() == AxisState::Idle || axis.input_vel() == 0.0f;
  };
  EXPECT_TRUE(rig.run_until([&] { return stopped(rig.left()) && stopped(rig.right()); }, 2))
      << "an axis is still driven";
}

// The other device answers commands and streams data throughout `seconds`.
void expect_other_device_served(OdriveRig& rig, double seconds) {
  const uint64_t before = rig.other().count;
  const float x0 = rig.other().x;
  rig.client.command_vel(OdriveRig::kOther, 0.5f, 0);
  rig.run_for(seconds);
  rig.client.command_vel(OdriveRig::kOther, 0, 0);
  EXPECT_GE(rig.other().count, before + uint64_t(seconds * 20 * 0.5)) << "kinematic data stopped flowing";
  EXPECT_GT(rig.other().x, x0) << "kinematic base did not follow its command";
}

TEST(OdriveFaults, SilentNodeStopsBothAndRecovers) {
  OdriveRig rig;
  start_driving(rig);
  rig.emu->set_silent(OdriveRig::kRight, true);
  expect_stopped_and_reported(rig, "right axis (node 1) silent");
  EXPECT_EQ(rig.left().state(), AxisState::Idle);  // the healthy axis is stopped too
  expect_other_device_served(rig, 1.0);
  // Unheard, the silent axis's watchdog has disarmed it.
  EXPECT_EQ(rig.right().error(), axis_error::kWatchdogTimerExpired);
  EXPECT_TRUE(rig.base().stall);

  rig.emu->set_silent(OdriveRig::kRight, false);
  ASSERT_TRUE(rig.run_until([&] { return recovered(rig); }, 5)) << rig.base().fault;
  EXPECT_EQ(rig.right().error(), 0u);  // cleared on the way back
  // The command given before the fault still holds.
  ASSERT_TRUE(rig.run_until([&] { return rig.right().velocity() > 0.5f; }, 3));
}

TEST(OdriveFaults, AxisErrorStopsBothAndRecovers) {
  OdriveRig rig;
  start_driving(rig);
  rig.left().inject_error(axis_error::kMotorFailed, /*persistent=*/false);
  expect_stopped_and_reported(rig, "left axis (node 0) error 0x40 MOTOR_FAILED");
  EXPECT_EQ(rig.right().state(), AxisState::Idle);
  ASSERT_TRUE(rig.run_until([&] { return recovered(rig); }, 5)) << rig.base().fault;
  EXPECT_EQ(rig.left().error(), 0u);
}

TEST(OdriveFaults, PersistentErrorKeepsTheBaseStoppedUntilCleared) {
  OdriveRig rig(with_options(R"("retry_delay_ms": 200, "retry_max_ms": 800)"));
  start_driving(rig);
  rig.right().inject_error(axis_error::kEncoderFailed, /*persistent=*/true);
  expect_stopped_and_reported(rig, "right axis (node 1)");
  // Several recovery attempts fail; the base stays stopped and reported,
  // the node keeps serving.
  expect_other_device_served(rig, 2.5);
  EXPECT_TRUE(rig.base().stall);
  EXPECT_NE(rig.base().fault.find("ENCODER_FAILED"), std::string::npos) << rig.base().fault;
  EXPECT_EQ(rig.right().state(), AxisState::Idle);
  EXPECT_TRUE(rig.left().state() == AxisState::Idle || rig.left().input_vel() == 0.0f);

  rig.right().clear_fault();  // the cause is gone: the next attempt succeeds
  ASSERT_TRUE(rig.run_until([&] { return recovered(rig); }, 5)) << rig.base().fault;
}

TEST(OdriveFaults, DroppedFramesBurstStopsAndRecovers) {
  OdriveRig rig;
  start_driving(rig);
  rig.emu->set_drop_probability(1.0);  // the bus loses everything
  expect_stopped_and_reported(rig, "silent");
  // The driver's stop frames were lost too: the axes' watchdogs stopped them.
  EXPECT_EQ(rig.left().error(), axis_error::kWatchdogTimerExpired);
  EXPECT_EQ(rig.right().error(), axis_error::kWatchdogTimerExpired);
  expect_other_device_served(rig, 0.5);
  rig.emu->set_drop_probability(0);
  ASSERT_TRUE(rig.run_until([&] { return recovered(rig); }, 5)) << rig.base().fault;
  EXPECT_GT(rig.emu->counters().dropped_in, 0u);
  EXPECT_GT(rig.emu->counters().dropped_out, 0u);
}

TEST(OdriveFaults, RandomlyDroppedFramesDoNotStopTheBase) {
  RigConfig config;
  config.seed = 7;
  OdriveRig rig(config);
  start_driving(rig);
  // One frame in ten lost each way: heartbeats still come well within the
  // 350 ms timeout, so the driver keeps driving.
  rig.emu->set_drop_probability(0.1);
  const float x0 = rig.base().x;
  rig.run_for(2.0);
  EXPECT_GT(rig.base().x, x0 + 0.4f);
  EXPECT_GT(rig.emu->counters().dropped_in + rig.emu->counters().dropped_out, 20u);
  rig.emu->set_drop_probability(0);
  ASSERT_TRUE(rig.run_until([&] { return recovered(rig); }, 5)) << rig.base().fault;
}

TEST(OdriveFaults, GarbageFramesAreIgnored) {
  OdriveRig rig;
  ASSERT_EQ(rig.error(), "");
  ASSERT_TRUE(rig.run_until([&] { return recovered(rig) && rig.base().count > 0; }, 5));
  rig.emu->send_garbage(OdriveRig::kLeft, 100);
  rig.emu->send_garbage(OdriveRig::kRight, 100);
  expect_other_device_served(rig, 0.5);
  EXPECT_TRUE(recovered(rig)) << rig.base().fault;
  // Short frames carried a position of 1e9 turns: none reached odometry.
  EXPECT_NEAR(rig.base().x, 0, 1e-4);
  EXPECT_NEAR(rig.base().a, 0, 1e-4);
}

TEST(OdriveFaults, RebootedAxisDoesNotTeleportTheOdometry) {
  OdriveRig rig(with_options(R"("max_wheel_turns_s": 2)"));
  start_driving(rig);
  ASSERT_TRUE(rig.run_until([&] { return rig.left().position_turns() > 1.5; }, 5));
  rig.client.command_vel(OdriveRig::kBase, 0, 0);
  ASSERT_TRUE(rig.run_until([&] { return std::fabs(rig.left().velocity()) < 1e-4f; }, 3));
  rig.run_for(0.1);
  const float x_before = rig.base().x;
  const float a_before = rig.base().a;
  ASSERT_GT(x_before, 0.7f);
  rig.left().reboot(rig.node.loop().now_us());  // its position count restarts at 0
  expect_stopped_and_reported(rig, "left axis (node 0)");
  ASSERT_TRUE(rig.run_until([&] { return recovered(rig); }, 5)) << rig.base().fault;
  // The jump from 1.5 turns to 0 was refused, not integrated as 0.75 m back.
  EXPECT_NEAR(rig.base().x, x_before, 1e-3);
  EXPECT_NEAR(rig.base().a, a_before, 1e-3);
  // And odometry goes on from there.
  rig.client.command_vel(OdriveRig::kBase, 0.3f, 0);
  ASSERT_TRUE(rig.run_until([&] { return rig.base().x > x_before + 0.2f; }, 5));
  EXPECT_NEAR(rig.base().a, a_before, 0.02);
}

TEST(OdriveFaults, BusGoneStopsTheDriverNotTheNode) {
  OdriveRig rig;
  if (!rig.can_interface().empty()) GTEST_SKIP() << "socketpair only; kernel_bus_test removes the interface";
  start_driving(rig);
  rig.close_bus();
  ASSERT_TRUE(rig.run_until([&] { return rig.base().stall; }, 3));
  EXPECT_NE(rig.base().fault.find("CAN bus lost"), std::string::npos) << rig.base().fault;
  expect_other_device_served(rig, 1.0);
  // Position2d goes on reporting the stall.
  const uint64_t n = rig.base().count;
  rig.run_for(0.3);
  EXPECT_GT(rig.base().count, n);
  EXPECT_TRUE(rig.base().stall);
  uint32_t on = rig.client.request_motor_power(OdriveRig::kBase, true);
  ASSERT_TRUE(rig.run_until([&] { return rig.client.reply(on).kind != wire::Kind::Invalid; }, 2));
  EXPECT_EQ(rig.client.reply(on).kind, wire::Kind::Nack);
  EXPECT_NE(rig.client.reply(on).text.find("CAN bus is down"), std::string::npos);
}

TEST(OdriveFaults, EstopFromElsewhereNeedsMotorPowerToClear) {
  OdriveRig rig;
  start_driving(rig);
  // Another host on the bus hits the emergency stop of one axis.
  rig.emu->axis(OdriveRig::kLeft)->inject_error(axis_error::kEstopRequested, false);
  expect_stopped_and_reported(rig, "ESTOP_REQUESTED");
  rig.run_for(1.5);  // longer than the first retry delay: no automatic recovery
  EXPECT_TRUE(rig.base().stall);
  EXPECT_EQ(rig.left().state(), AxisState::Idle);
  uint32_t on = rig.client.request_motor_power(OdriveRig::kBase, true);
  ASSERT_TRUE(rig.run_until([&] { return recovered(rig); }, 3)) << rig.base().fault;
  EXPECT_EQ(rig.client.reply(on).kind, wire::Kind::Ack);
}

TEST(OdriveFaults, AxesNeverHeardReportAFault) {
  RigConfig config;
  emulators::odrive::AxisConfig only_left;
  only_left.node_id = OdriveRig::kLeft;
  config.axes = {only_left};  // the right axis is not on the bus at all
  OdriveRig rig(config);
  ASSERT_EQ(rig.error(), "");
  ASSERT_TRUE(rig.run_until([&] { return rig.base().stall; }, 3));
  EXPECT_NE(rig.base().fault.find("no heartbeat from the right axis (node 1)"), std::string::npos)
      << rig.base().fault;
  EXPECT_EQ(rig.left().state(), AxisState::Idle);
  expect_other_device_served(rig, 0.5);
}

}  // namespace
}  // namespace troupe::testing
