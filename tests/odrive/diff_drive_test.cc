// Differential-drive arithmetic and wrap-safe position tracking.
#include "drivers/odrive_can/diff_drive.h"

#include <gtest/gtest.h>

#include <cmath>

namespace troupe::drivers::odrive_can {
namespace {

constexpr double kPi = 3.141592653589793;
const DriveGeometry kGeometry{0.1f, 0.5f, false, false};

TEST(DiffDrive, WheelRatesAndBackAgain) {
  WheelTurnRates r = wheel_rates(1.0f, 2.0f, kGeometry, 100);
  // Left wheel: 1 - 2 * 0.25 = 0.5 m/s; right: 1.5 m/s; 0.628 m per turn.
  EXPECT_NEAR(r.left, 0.5 / (2 * kPi * 0.1), 1e-6);
  EXPECT_NEAR(r.right, 1.5 / (2 * kPi * 0.1), 1e-6);
  float v = 0, w = 0;
  body_velocity(r, kGeometry, v, w);
  EXPECT_NEAR(v, 1.0f, 1e-6);
  EXPECT_NEAR(w, 2.0f, 1e-6);
}

TEST(DiffDrive, InvertedSideChangesSignBothWays) {
  DriveGeometry g = kGeometry;
  g.invert_right = true;
  WheelTurnRates r = wheel_rates(0.5f, 0, g, 100);
  EXPECT_GT(r.left, 0);
  EXPECT_FLOAT_EQ(r.right, -r.left);
  float v = 0, w = 0;
  body_velocity(r, g, v, w);
  EXPECT_NEAR(v, 0.5f, 1e-6);
  EXPECT_NEAR(w, 0.0f, 1e-6);
}

TEST(DiffDrive, WheelLimitScalesBothKeepingCurvature) {
  WheelTurnRates free = wheel_rates(2.0f, 1.0f, kGeometry, 100);
  WheelTurnRates held = wheel_rates(2.0f, 1.0f, kGeometry, 1.0f);
  EXPECT_FLOAT_EQ(std::max(std::fabs(held.left), std::fabs(held.right)), 1.0f);
  EXPECT_NEAR(held.left / held.right, free.left / free.right, 1e-6);
}

TEST(DiffDrive, IntegratesAStraightLineAndAFullCircle) {
  Odometry odom;
  for (int i = 0; i < 100; ++i) integrate(odom, 0.01, 0.01, 0.5);
  EXPECT_NEAR(odom.x, 1.0, 1e-9);
  EXPECT_NEAR(odom.y, 0.0, 1e-9);
  // Right wheel on a 1 m radius circle, left on 0.5 m: centre radius 0.75 m.
  Odometry circle;
  const int steps = 1000;
  for (int i = 0; i < steps; ++i) integrate(circle, 2 * kPi * 0.5 / steps, 2 * kPi * 1.0 / steps, 0.5);
  EXPECT_NEAR(circle.x, 0.0, 1e-6);
  EXPECT_NEAR(circle.y, 0.0, 1e-6);
  EXPECT_NEAR(circle.a, 0.0, 1e-9);
  // A quarter of it ends at (r, r) with heading pi/2.
  Odometry quarter;
  for (int i = 0; i < steps / 4; ++i) integrate(quarter, 2 * kPi * 0.5 / steps, 2 * kPi * 1.0 / steps, 0.5);
  EXPECT_NEAR(quarter.x, 0.75, 1e-9);
  EXPECT_NEAR(quarter.y, 0.75, 1e-9);
  EXPECT_NEAR(quarter.a, kPi / 2, 1e-9);
}

TEST(PositionTracker, LinearCountAndFloatSteps) {
  PositionTracker t;
  t.configure(0, 10);
  double d = 0, total = 0;
  EXPECT_EQ(t.update(100.0f, 0, d), PositionTracker::Step::First);
  for (int i = 1; i <= 100; ++i) {
    ASSERT_EQ(t.update(100.0f + 0.05f * float(i), uint64_t(i) * 10000, d), PositionTracker::Step::Moved);
    total += d;
  }
  EXPECT_NEAR(total, 5.0, 1e-4);
}

TEST(PositionTracker, WrapsTheShortWayRound) {
  PositionTracker t;
  t.configure(1.0f, 10);
  double d = 0, total = 0;
  t.update(0.0f, 0, d);
  // 3.3 turns forward in 0.07-turn steps, reported modulo 1 turn.
  double truth = 0;
  for (int i = 1; i <= 47; ++i) {
    truth += 0.07;
    ASSERT_EQ(t.update(float(std::fmod(truth, 1.0)), uint64_t(i) * 10000, d), PositionTracker::Step::Moved);
    total += d;
  }
  EXPECT_NEAR(total, truth, 1e-5);
  // And back again across zero.
  for (int i = 48; i <= 94; ++i) {
    truth -= 0.07;
    ASSERT_EQ(t.update(float(std::fmod(std::fmod(truth, 1.0) + 1.0, 1.0)), uint64_t(i) * 10000, d),
              PositionTracker::Step::Moved);
    total += d;
  }
  EXPECT_NEAR(total, truth, 1e-5);
}

TEST(PositionTracker, RefusesJumpsFasterThanTheWheelAndResumes) {
  PositionTracker t;
  t.configure(0, 2.0f);  // at most 2 turns/s: 0.45 turns judged over 0.1 s
  double d = 0;
  t.update(50.0f, 0, d);
  EXPECT_EQ(t.update(0.0f, 10000, d), PositionTracker::Step::Refused);  // a reboot's reset count
  EXPECT_EQ(d, 0.0);
  EXPECT_EQ(t.update(0.02f, 20000, d), PositionTracker::Step::Moved);  // tracking resumed from 0
  EXPECT_NEAR(d, 0.02, 1e-7);
  EXPECT_EQ(t.update(NAN, 30000, d), PositionTracker::Step::Refused);
  // A long gap allows a long move: 1 s at 2 turns/s.
  EXPECT_EQ(t.update(2.0f, 1030000, d), PositionTracker::Step::Moved);
  EXPECT_NEAR(d, 1.98, 1e-6);
}

}  // namespace
}  // namespace troupe::drivers::odrive_can
