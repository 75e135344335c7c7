// The kinematic driver's integration step: limits, straight lines and arcs.
#include <gtest/gtest.h>

#include <cmath>

#include "drivers/kinematic/kinematic.h"

namespace troupe::drivers::kinematic {
namespace {

constexpr Limits kLoose{10, 10, 1000, 1000};  // effectively no limits

TEST(KinematicStep, StraightLineAtConstantSpeed) {
  Base b;
  b.target_v = 0.5f;
  for (int i = 0; i < 100; ++i) step(b, kLoose, 0.01f);  // 1 s
  EXPECT_NEAR(b.x, 0.5f, 1e-4f);
  EXPECT_NEAR(b.y, 0.0f, 1e-6f);
  EXPECT_NEAR(b.a, 0.0f, 1e-6f);
}

TEST(KinematicStep, FullCircleReturnsToTheStart) {
  Base b;
  b.target_v = 1.0f;
  b.target_w = 1.0f;  // radius 1 m, period 2*pi s
  int steps = 6283;
  for (int i = 0; i < steps; ++i) step(b, kLoose, 0.001f);
  EXPECT_NEAR(b.x, 0.0f, 2e-3f);
  EXPECT_NEAR(b.y, 0.0f, 2e-3f);
  // Halfway round it is 2 m to the left.
  Base h;
  h.target_v = 1.0f;
  h.target_w = 1.0f;
  for (int i = 0; i < 3142; ++i) step(h, kLoose, 0.001f);
  EXPECT_NEAR(h.x, 0.0f, 2e-3f);
  EXPECT_NEAR(h.y, 2.0f, 2e-3f);
  EXPECT_NEAR(std::fabs(h.a), 3.14159f, 2e-3f);
}

TEST(KinematicStep, AccelerationIsLimited) {
  Limits lim{2.0f, 2.0f, 0.5f, 1.0f};
  Base b;
  b.target_v = 1.0f;
  step(b, lim, 0.1f);
  EXPECT_NEAR(b.v, 0.05f, 1e-6f);  // 0.5 m/s^2 for 0.1 s
  for (int i = 0; i < 30; ++i) step(b, lim, 0.1f);
  EXPECT_NEAR(b.v, 1.0f, 1e-6f);
  // Distance covered while ramping up over 2 s: v^2 / (2a) = 1 m.
  Base c;
  c.target_v = 1.0f;
  for (int i = 0; i < 2000; ++i) step(c, lim, 0.001f);
  EXPECT_NEAR(c.x, 1.0f, 2e-3f);
}

TEST(KinematicStep, SpeedAndTurnRateAreClamped) {
  Limits lim{0.3f, 0.5f, 100, 100};
  Base b;
  b.target_v = 5.0f;
  b.target_w = -5.0f;
  for (int i = 0; i < 10; ++i) step(b, lim, 0.1f);
  EXPECT_FLOAT_EQ(b.v, 0.3f);
  EXPECT_FLOAT_EQ(b.w, -0.5f);
}

TEST(KinematicStep, HeadingStaysWrapped) {
  Base b;
  b.target_w = 3.0f;
  for (int i = 0; i < 10000; ++i) {
    step(b, kLoose, 0.01f);
    ASSERT_LE(std::fabs(b.a), 3.14160f);
  }
}

}  // namespace
}  // namespace troupe::drivers::kinematic
