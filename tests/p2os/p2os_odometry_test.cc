// Odometry from SIP counters: 15-bit wrap, conversion factors, rejected
// jumps, frame changes and the SETO reset.
#include "drivers/p2os/p2os_odometry.h"

#include <gtest/gtest.h>

#include <cmath>

namespace troupe::drivers::p2os {
namespace {

constexpr double kPi = 3.14159265358979323846;

Sip sip_at(int x, int y, int heading = 0, int left = 0, int right = 0) {
  Sip s;
  s.type = 0x32;
  s.x = uint16_t(x & 0x7FFF);
  s.y = uint16_t(y & 0x7FFF);
  s.heading = int16_t(heading);
  s.left_vel = int16_t(left);
  s.right_vel = int16_t(right);
  return s;
}

TEST(P2osOdometry, WrapDeltaTakesTheShortWayRound) {
  EXPECT_EQ(wrap_delta(10, 20, 0x8000), 10);
  EXPECT_EQ(wrap_delta(20, 10, 0x8000), -10);
  EXPECT_EQ(wrap_delta(0x7FF0, 0x0010, 0x8000), 0x20);
  EXPECT_EQ(wrap_delta(0x0010, 0x7FF0, 0x8000), -0x20);
}

TEST(P2osOdometry, AccumulatesAcrossTheCounterWrap) {
  const RobotParams& p3dx_sh = *find_robot("p3dx-sh");
  Odometry odo(p3dx_sh);
  EXPECT_EQ(odo.update(sip_at(32700, 0)), Odometry::Update::First);
  EXPECT_DOUBLE_EQ(odo.pose().x, 0);
  // 50 mm per SIP for 40 SIPs: the counter wraps past 32767 on the way.
  int x = 32700;
  for (int i = 0; i < 40; ++i) {
    x += 50;
    ASSERT_EQ(odo.update(sip_at(x, 0)), Odometry::Update::Moved);
  }
  EXPECT_NEAR(odo.pose().x, 2.0, 1e-9);
  // And back, through the wrap the other way.
  for (int i = 0; i < 80; ++i) {
    x -= 50;
    odo.update(sip_at(x, 0));
  }
  EXPECT_NEAR(odo.pose().x, -2.0, 1e-9);
}

TEST(P2osOdometry, AppliesTheModelsDistanceFactor) {
  Odometry odo(*find_robot("p3dx"));  // DistConvFactor 0.485 mm per count
  odo.update(sip_at(0, 0));
  odo.update(sip_at(100, 200));
  EXPECT_NEAR(odo.pose().x, 0.0485, 1e-9);
  EXPECT_NEAR(odo.pose().y, 0.0970, 1e-9);
}

TEST(P2osOdometry, ACorruptedSipCostsNothing) {
  Odometry odo(*find_robot("p3dx-sh"));
  odo.update(sip_at(1000, 1000));
  odo.update(sip_at(1090, 1000));
  // x with bit 12 flipped, yet a matching checksum.
  EXPECT_EQ(odo.update(sip_at(1100 ^ 0x1000, 1000)), Odometry::Update::JumpRejected);
  EXPECT_NEAR(odo.pose().x, 0.090, 1e-9);
  // The next good SIP counts from the last good one: nothing is lost.
  EXPECT_EQ(odo.update(sip_at(1110, 1000)), Odometry::Update::Moved);
  EXPECT_NEAR(odo.pose().x, 0.110, 1e-9);
}

TEST(P2osOdometry, CountersResetBehindOurBackBecomeTheReference) {
  Odometry odo(*find_robot("p3dx-sh"));
  odo.update(sip_at(1000, 1000));
  odo.update(sip_at(1090, 1000));
  EXPECT_EQ(odo.update(sip_at(5000, 0)), Odometry::Update::JumpRejected);
  EXPECT_EQ(odo.update(sip_at(5010, 0)), Odometry::Update::JumpRejected);
  EXPECT_EQ(odo.update(sip_at(5020, 0)), Odometry::Update::JumpAccepted);
  EXPECT_NEAR(odo.pose().x, 0.090, 1e-9);
  EXPECT_EQ(odo.update(sip_at(5030, 0)), Odometry::Update::Moved);
  EXPECT_NEAR(odo.pose().x, 0.100, 1e-9);
}

TEST(P2osOdometry, HeadingComesFromTheCounter) {
  Odometry odo(*find_robot("p3dx-sh"));
  odo.update(sip_at(0, 0, 0));
  odo.update(sip_at(0, 0, 1024));  // a quarter turn
  EXPECT_NEAR(odo.pose().a, 1024 * 0.001534, 1e-9);
  odo.update(sip_at(0, 0, 3072));  // three quarters: reported as -pi/2
  EXPECT_NEAR(odo.pose().a, 3072 * 0.001534 - 2 * kPi, 1e-9);
}

TEST(P2osOdometry, SetPoseMovesTheFrame) {
  Odometry odo(*find_robot("p3dx-sh"));
  for (int x = 0; x <= 500; x += 50) odo.update(sip_at(x, 0, 0));
  odo.set_pose({10, 20, kPi / 2});
  EXPECT_NEAR(odo.pose().x, 10, 1e-9);
  EXPECT_NEAR(odo.pose().a, kPi / 2, 1e-9);
  // Driving on along the robot's x is now along the new frame's y.
  for (int x = 550; x <= 1000; x += 50) odo.update(sip_at(x, 0, 0));
  EXPECT_NEAR(odo.pose().x, 10, 1e-9);
  EXPECT_NEAR(odo.pose().y, 20.5, 1e-9);
}

TEST(P2osOdometry, ResetWaitsForTheRobotsCountersToRestart) {
  Odometry odo(*find_robot("p3dx-sh"));
  odo.update(sip_at(3000, 4000, 0));
  odo.update(sip_at(3050, 4000, 0));
  odo.reset();
  EXPECT_NEAR(odo.pose().x, 0, 1e-9);
  EXPECT_NEAR(odo.pose().a, 0, 1e-9);
  // One SIP still carries the old counters (sent before SETO arrived).
  EXPECT_EQ(odo.update(sip_at(3060, 4000, 0, 100, 100)), Odometry::Update::Moved);
  EXPECT_NEAR(odo.pose().x, 0.010, 1e-9);
  // Then the counters restart near zero: a jump, but not a rejected one.
  EXPECT_EQ(odo.update(sip_at(12, 0, 0, 100, 100)), Odometry::Update::Rebased);
  EXPECT_NEAR(odo.pose().x, 0.012, 1e-9);
  EXPECT_NEAR(odo.pose().a, 0, 1e-9);
  EXPECT_FALSE(odo.reset_pending());
  EXPECT_EQ(odo.update(sip_at(40, 0, 0)), Odometry::Update::Moved);
  EXPECT_NEAR(odo.pose().x, 0.040, 1e-9);
}

TEST(P2osOdometry, ResetCarriesOnWhenTheRobotIgnoresSeto) {
  Odometry odo(*find_robot("p3dx-sh"));
  odo.update(sip_at(3000, 4000, 0));
  odo.reset();
  Odometry::Update last{};
  for (int i = 1; i <= Odometry::kResetWaitSips; ++i) last = odo.update(sip_at(3000 + 10 * i, 4000, 0));
  EXPECT_EQ(last, Odometry::Update::ResetIgnored);
  EXPECT_FALSE(odo.reset_pending());
  EXPECT_NEAR(odo.pose().x, 0.010 * Odometry::kResetWaitSips, 1e-9);
}

TEST(P2osOdometry, ARestartedSessionContinuesThePose) {
  Odometry odo(*find_robot("p3dx-sh"));
  odo.update(sip_at(0, 0, 0));
  odo.update(sip_at(80, 0, 0));
  // The robot was power-cycled while the driver reconnected: its counters
  // and heading restart, the reported pose does not jump.
  odo.restart();
  EXPECT_EQ(odo.update(sip_at(0, 0, 2048)), Odometry::Update::First);
  EXPECT_NEAR(odo.pose().x, 0.080, 1e-9);
  EXPECT_NEAR(odo.pose().a, 0, 1e-9);
}

}  // namespace
}  // namespace troupe::drivers::p2os
