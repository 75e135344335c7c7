// The odrive_can driver inside a real node, against the ODrive emulator over
// a socketpair carrying struct can_frame bytes, observed through a TCP
// client: arming, driving, odometry against the emulated wheels, requests.
// Faults are in fault_test.cc.
#include <gtest/gtest.h>

#include <cmath>

#include "drivers/odrive_can/cansimple.h"
#include "tests/odrive/odrive_rig.h"

namespace troupe::testing {
namespace {

using cansimple::AxisState;

constexpr double kTwoPi = 6.283185307179586;
constexpr double kRadius = 0.08;  // the driver's default wheel_radius, m
constexpr double kTrack = 0.4;    // the driver's default track_width, m

bool running(OdriveRig& rig) {
  return rig.left().state() == AxisState::ClosedLoopControl &&
         rig.right().state() == AxisState::ClosedLoopControl;
}

// Distance a wheel of the emulator has rolled, m.
double rolled(const emulators::odrive::Axis& axis, bool inverted = false) {
  return (inverted ? -1 : 1) * axis.position_turns() * kTwoPi * kRadius;
}

TEST(OdriveDriver, ArmsBothAxesIntoVelocityControl) {
  OdriveRig rig;
  ASSERT_EQ(rig.error(), "");
  ASSERT_TRUE(rig.run_until([&] { return running(rig); }, 5));
  for (auto* axis : {&rig.left(), &rig.right()}) {
    EXPECT_EQ(axis->control_mode(), cansimple::ControlMode::Velocity);
    EXPECT_EQ(axis->input_mode(), cansimple::InputMode::VelRamp);
    EXPECT_FLOAT_EQ(axis->vel_limit(), 10.0f);  // max_wheel_turns_s default
    EXPECT_EQ(axis->error(), 0u);
  }
  // On a slow machine (the VM's software emulation) the driver's first
  // heartbeat watch may expire before the emulator's first heartbeat; it then
  // recovers by itself. What matters is that it ends up running, unstalled.
  ASSERT_TRUE(rig.run_until([&] { return rig.base().count > 3 && !rig.base().stall; }, 10));
  EXPECT_EQ(rig.base().fault, "");
}

TEST(OdriveDriver, DrivesStraightAndOdometryFollowsTheWheels) {
  OdriveRig rig;
  ASSERT_EQ(rig.error(), "");
  ASSERT_TRUE(rig.run_until([&] { return running(rig); }, 5));
  rig.client.command_vel(OdriveRig::kBase, 0.5f, 0);
  // 0.5 m/s on 0.08 m wheels: 0.995 turns/s on both axes.
  ASSERT_TRUE(rig.run_until([&] { return rig.left().input_vel() > 0.9f; }, 2));
  EXPECT_NEAR(rig.left().input_vel(), 0.5 / (kTwoPi * kRadius), 1e-4);
  EXPECT_NEAR(rig.right().input_vel(), 0.5 / (kTwoPi * kRadius), 1e-4);
  rig.run_for(1.5);
  EXPECT_NEAR(rig.base().vx, 0.5, 0.02);
  rig.client.command_vel(OdriveRig::kBase, 0, 0);
  ASSERT_TRUE(rig.run_until([&] { return std::fabs(rig.left().velocity()) < 1e-4f; }, 3));
  rig.run_for(0.1);
  const double truth = 0.5 * (rolled(rig.left()) + rolled(rig.right()));
  EXPECT_GT(truth, 0.5);
  EXPECT_NEAR(rig.base().x, truth, 2e-3);
  EXPECT_NEAR(rig.base().y, 0, 1e-3);
  EXPECT_NEAR(rig.base().a, 0, 1e-3);
}

TEST(OdriveDriver, InvertedSideTurnsBackwardsForForwardTravel) {
  OdriveRig rig(with_options(R"("invert_right": true)"));
  ASSERT_EQ(rig.error(), "");
  ASSERT_TRUE(rig.run_until([&] { return running(rig); }, 5));
  rig.client.command_vel(OdriveRig::kBase, 0.3f, 0);
  ASSERT_TRUE(rig.run_until([&] { return rig.right().position_turns() < -0.3; }, 3));
  EXPECT_NEAR(rig.right().input_vel(), -0.3 / (kTwoPi * kRadius), 1e-4);
  EXPECT_GT(rig.left().position_turns(), 0.3);
  rig.run_for(0.1);
  EXPECT_GT(rig.base().x, 0.1);  // forward, not turning on the spot
  EXPECT_NEAR(rig.base().a, 0, 0.02);
}

TEST(OdriveDriver, TurnsOnTheSpot) {
  OdriveRig rig;
  ASSERT_EQ(rig.error(), "");
  ASSERT_TRUE(rig.run_until([&] { return running(rig); }, 5));
  rig.client.command_vel(OdriveRig::kBase, 0, 1.0f);
  // w = 1 rad/s: wheels at -/+ 0.2 m/s.
  ASSERT_TRUE(rig.run_until([&] { return rig.base().a > 1.0f; }, 5));
  EXPECT_NEAR(rig.left().input_vel(), -0.2 / (kTwoPi * kRadius), 1e-4);
  EXPECT_NEAR(rig.right().input_vel(), 0.2 / (kTwoPi * kRadius), 1e-4);
  rig.client.command_vel(OdriveRig::kBase, 0, 0);
  ASSERT_TRUE(rig.run_until([&] { return std::fabs(rig.right().velocity()) < 1e-4f; }, 3));
  rig.run_for(0.1);
  const double heading = (rolled(rig.right()) - rolled(rig.left())) / kTrack;
  EXPECT_NEAR(rig.base().a, std::remainder(heading, kTwoPi), 2e-3);
  EXPECT_NEAR(rig.base().x, 0, 2e-3);
  EXPECT_NEAR(rig.base().y, 0, 2e-3);
}

TEST(OdriveDriver, SpeedLimitsKeepTheCurvature) {
  OdriveRig rig(with_options(R"("max_wheel_turns_s": 1.0, "max_speed": 5)"));
  ASSERT_EQ(rig.error(), "");
  ASSERT_TRUE(rig.run_until([&] { return running(rig); }, 5));
  rig.client.command_vel(OdriveRig::kBase, 2.0f, 2.0f);  // wants 3.18 and 4.77 turns/s
  ASSERT_TRUE(rig.run_until([&] { return rig.right().input_vel() > 0.5f; }, 2));
  EXPECT_NEAR(rig.right().input_vel(), 1.0, 1e-4);
  EXPECT_NEAR(rig.left().input_vel(), (2.0 - 2.0 * kTrack / 2) / (2.0 + 2.0 * kTrack / 2), 1e-4);
  EXPECT_FLOAT_EQ(rig.right().vel_limit(), 1.0f);
}

TEST(OdriveDriver, OdometryThroughWrappingPositions) {
  // Axes reporting within [0, 1) turn: many wraps a second at 2.5 turns/s.
  RigConfig config = with_options(R"("position_wrap_turns": 1.0)");
  for (uint8_t id : {OdriveRig::kLeft, OdriveRig::kRight}) {
    emulators::odrive::AxisConfig a;
    a.node_id = id;
    a.wrap_turns = 1.0f;
    config.axes.push_back(a);
  }
  OdriveRig rig(config);
  ASSERT_EQ(rig.error(), "");
  ASSERT_TRUE(rig.run_until([&] { return running(rig); }, 5));
  rig.client.command_vel(OdriveRig::kBase, 1.25f, 0);
  ASSERT_TRUE(rig.run_until([&] { return rig.left().position_turns() > 5; }, 5));
  rig.client.command_vel(OdriveRig::kBase, 0, 0);
  ASSERT_TRUE(rig.run_until([&] { return std::fabs(rig.left().velocity()) < 1e-4f; }, 3));
  rig.run_for(0.1);
  EXPECT_NEAR(rig.base().x, 0.5 * (rolled(rig.left()) + rolled(rig.right())), 3e-3);
  EXPECT_FALSE(rig.base().stall);
}

TEST(OdriveDriver, PublishesBusVoltage) {
  OdriveRig rig;
  ASSERT_EQ(rig.error(), "");
  ASSERT_TRUE(rig.run_until([&] { return rig.client.power(OdriveRig::kPower).count >= 2; }, 5));
  // 24 V supply, 0.05 ohm, two axes drawing 0.3 A or more.
  EXPECT_LT(rig.client.power(OdriveRig::kPower).volts, 24.0f);
  EXPECT_GT(rig.client.power(OdriveRig::kPower).volts, 23.0f);
}

TEST(OdriveDriver, MotorPowerOffIdlesBothAxesAndOnRearms) {
  OdriveRig rig;
  ASSERT_EQ(rig.error(), "");
  ASSERT_TRUE(rig.run_until([&] { return running(rig); }, 5));
  rig.client.command_vel(OdriveRig::kBase, 0.3f, 0);
  uint32_t off = rig.client.request_motor_power(OdriveRig::kBase, false);
  ASSERT_TRUE(rig.run_until(
      [&] { return rig.left().state() == AxisState::Idle && rig.right().state() == AxisState::Idle; }, 2));
  EXPECT_EQ(rig.client.reply(off).kind, wire::Kind::Ack);
  rig.run_for(0.5);
  EXPECT_EQ(rig.left().state(), AxisState::Idle);  // stays off, no retry
  EXPECT_EQ(rig.left().input_vel(), 0.0f);
  EXPECT_FALSE(rig.base().stall);
  uint32_t on = rig.client.request_motor_power(OdriveRig::kBase, true);
  ASSERT_TRUE(rig.run_until([&] { return running(rig); }, 3));
  EXPECT_EQ(rig.client.reply(on).kind, wire::Kind::Ack);
  // The command given before power-off holds again (Player's semantics).
  ASSERT_TRUE(rig.run_until([&] { return rig.left().velocity() > 0.5f; }, 3));
}

TEST(OdriveDriver, OdometryRequests) {
  OdriveRig rig;
  ASSERT_EQ(rig.error(), "");
  uint32_t set = rig.client.request_set_odometry(OdriveRig::kBase, 1.0f, 2.0f, 0.5f);
  ASSERT_TRUE(rig.run_until([&] { return rig.client.reply(set).kind == wire::Kind::Ack; }, 2));
  rig.run_for(0.1);
  EXPECT_FLOAT_EQ(rig.base().x, 1.0f);
  EXPECT_FLOAT_EQ(rig.base().y, 2.0f);
  EXPECT_FLOAT_EQ(rig.base().a, 0.5f);
  uint32_t reset = rig.client.request_reset_odometry(OdriveRig::kBase);
  ASSERT_TRUE(rig.run_until([&] { return rig.client.reply(reset).kind == wire::Kind::Ack; }, 2));
  rig.run_for(0.1);
  EXPECT_EQ(rig.base().x, 0.0f);
  uint32_t geometry = rig.client.request_geometry(OdriveRig::kBase);
  ASSERT_TRUE(rig.run_until([&] { return rig.client.reply(geometry).kind == wire::Kind::Ack; }, 2));
  EXPECT_FLOAT_EQ(rig.client.geometry_length, 0.5f);
  EXPECT_FLOAT_EQ(rig.client.geometry_width, 0.45f);
}

TEST(OdriveDriver, CommandTimeoutStopsTheWheels) {
  OdriveRig rig(with_options(R"("command_timeout_ms": 300)"));
  ASSERT_EQ(rig.error(), "");
  ASSERT_TRUE(rig.run_until([&] { return running(rig); }, 5));
  rig.client.command_vel(OdriveRig::kBase, 0.4f, 0);
  ASSERT_TRUE(rig.run_until([&] { return rig.left().input_vel() > 0.5f; }, 2));
  ASSERT_TRUE(rig.run_until([&] { return rig.left().input_vel() == 0.0f; }, 2));
  EXPECT_TRUE(running(rig));  // stopped, still armed
}

TEST(OdriveDriver, ShutdownLeavesBothAxesIdle) {
  OdriveRig rig;
  ASSERT_EQ(rig.error(), "");
  ASSERT_TRUE(rig.run_until([&] { return running(rig); }, 5));
  rig.client.command_vel(OdriveRig::kBase, 0.3f, 0);
  rig.run_for(0.3);
  rig.node.shutdown();
  for (int i = 0; i < 5; ++i) rig.node.loop().run_once(2000);
  EXPECT_EQ(rig.left().state(), AxisState::Idle);
  EXPECT_EQ(rig.right().state(), AxisState::Idle);
  EXPECT_EQ(rig.left().input_vel(), 0.0f);
  EXPECT_EQ(rig.left().error(), 0u);
}

TEST(OdriveDriver, ShutdownWithEstopLatchesTheEstopError) {
  OdriveRig rig(with_options(R"("estop_on_shutdown": true)"));
  ASSERT_EQ(rig.error(), "");
  ASSERT_TRUE(rig.run_until([&] { return running(rig); }, 5));
  rig.node.shutdown();
  for (int i = 0; i < 5; ++i) rig.node.loop().run_once(2000);
  for (auto* axis : {&rig.left(), &rig.right()}) {
    EXPECT_EQ(axis->state(), AxisState::Idle);
    EXPECT_EQ(axis->error(), cansimple::axis_error::kEstopRequested);
  }
}

}  // namespace
}  // namespace troupe::testing
