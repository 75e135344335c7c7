#include "wire/geometry.h"

#include <gtest/gtest.h>

namespace troupe::geometry {
namespace {

TEST(Geometry, WrapAngleFoldsIntoPlusMinusPi) {
  EXPECT_DOUBLE_EQ(wrap_angle(3 * kPi / 2), -kPi / 2);
  EXPECT_DOUBLE_EQ(wrap_angle(-3 * kPi / 2), kPi / 2);
  EXPECT_DOUBLE_EQ(wrap_angle(0.25 + 8 * kPi), 0.25);
  EXPECT_LE(std::abs(wrap_angle(kPi)), kPi);
}

TEST(Geometry, ComposeAndRelativeAreInverse) {
  const Pose2 frame{1.0, -2.0, 0.7}, local{0.3, 0.4, -2.0};
  Pose2 world = compose(frame, local);
  Pose2 back = relative(frame, world);
  EXPECT_NEAR(back.x, local.x, 1e-12);
  EXPECT_NEAR(back.y, local.y, 1e-12);
  EXPECT_NEAR(back.a, local.a, 1e-12);
  EXPECT_EQ(frame.compose(local), world);
  Vec2 p = frame.to_world({0.3, 0.4});
  EXPECT_EQ(p, (Vec2{world.x, world.y}));
  Vec2 q = frame.to_local(p);
  EXPECT_NEAR(q.x, 0.3, 1e-12);
  EXPECT_NEAR(q.y, 0.4, 1e-12);
}

TEST(Geometry, ComposeTurnsTheLocalOffset) {
  Pose2 p = compose({1, 1, kPi / 2}, {1, 0, 0});
  EXPECT_NEAR(p.x, 1, 1e-15);
  EXPECT_NEAR(p.y, 2, 1e-15);
  EXPECT_NEAR(p.a, kPi / 2, 1e-15);
}

TEST(Geometry, InterpolateTakesTheShortArc) {
  Pose2 m = interpolate({0, 0, 3.0}, {2, 4, -3.0}, 0.5);
  EXPECT_DOUBLE_EQ(m.x, 1);
  EXPECT_DOUBLE_EQ(m.y, 2);
  EXPECT_NEAR(std::abs(m.a), kPi, 1e-9);
  EXPECT_DOUBLE_EQ(distance({0, 0, 0}, {3, 4, 1}), 5);
}

TEST(Geometry, VectorOperations) {
  EXPECT_EQ(rotate({1, 0}, kPi / 2).y, 1);
  EXPECT_EQ(cross(Vec2{1, 0}, Vec2{0, 1}), 1);
  EXPECT_EQ(cross(2.0, Vec2{1, 0}), (Vec2{0, 2}));
  EXPECT_EQ(normalized({0, 0}), (Vec2{1, 0}));
  EXPECT_EQ(normalized({0, 3}), (Vec2{0, 1}));
  EXPECT_EQ(perp({1, 2}), (Vec2{-2, 1}));
}

}  // namespace
}  // namespace troupe::geometry
