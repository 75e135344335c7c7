// The world step: impacts conserve momentum (and energy when elastic and
// frictionless), bounces follow restitution and friction, fast balls do
// not tunnel, heights let bodies pass, and runs are deterministic.
#include <gtest/gtest.h>

#include "host-sim/robocup/physics/world.h"

namespace troupe::robocup {
namespace {

constexpr double kBallRadius = 0.11;  // m, a size-5 football
constexpr double kBallMass = 0.43;    // kg

BodyDef ball_def(Vec2 at, Vec2 v) {
  BodyDef d;
  d.pose = {at.x, at.y, 0};
  d.velocity = {v.x, v.y, 0};
  d.mass = kBallMass;
  d.inertia = 2.0 / 5.0 * kBallMass * kBallRadius * kBallRadius;  // solid sphere
  d.shapes = {with_height(make_circle({0, 0}, kBallRadius), 0, 2 * kBallRadius)};
  return d;
}

BodyDef wall_def(Vec2 center, double length, double width) {
  BodyDef d;
  d.pose = {center.x, center.y, 0};
  d.shapes = {make_rect({0, 0}, length, width)};
  return d;
}

BodyId add(World& w, const BodyDef& d) {
  std::string error;
  BodyId id = w.create_body(d, error);
  EXPECT_TRUE(w.valid(id)) << error;
  return id;
}

WorldDef settings(double e, double f, double cycle = 0.01) {
  WorldDef def;
  def.restitution = e;
  def.friction = f;
  def.cycle_s = cycle;
  return def;
}

void run(World& w, double seconds) {
  const int n = int(std::lround(seconds / w.settings().cycle_s));
  for (int i = 0; i < n; ++i) w.step();
}

TEST(Impacts, ElasticFrictionlessOffCentreImpactConservesEverything) {
  World w(settings(1.0, 0.0));
  BodyId ball = add(w, ball_def({-1, 0.05}, {3, 0}));
  // A robot-sized box, turning, hit off its centre line.
  BodyDef box;
  box.pose = {0.5, -0.1, 0.3};
  box.velocity = {-0.5, 0.2, 1.5};
  box.mass = 20;
  box.shapes = {make_rect({0, 0}, 0.45, 0.4)};
  add(w, box);
  const double e0 = w.kinetic_energy();
  const Vec2 p0 = w.linear_momentum();
  const double l0 = w.angular_momentum({0, 0});
  const Twist ball_before = w.velocity(ball);
  run(w, 1.0);
  ASSERT_NE(w.velocity(ball), ball_before) << "no impact happened";
  EXPECT_NEAR(w.kinetic_energy(), e0, 1e-9 * e0);
  EXPECT_NEAR(w.linear_momentum().x, p0.x, 1e-9);
  EXPECT_NEAR(w.linear_momentum().y, p0.y, 1e-9);
  EXPECT_NEAR(w.angular_momentum({0, 0}), l0, 1e-9);
  EXPECT_NEAR(w.angular_momentum({3, -2}), l0 + cross(Vec2{0, 0} - Vec2{3, -2}, p0), 1e-9);
}

TEST(Impacts, InelasticAndFrictionalImpactsConserveMomentumAndLoseEnergy) {
  for (double f : {0.0, 0.5, 1.0}) {
    World w(settings(0.5, f));
    BodyId ball = add(w, ball_def({-1, 0.05}, {4, 0.1}));
    BodyDef e;
    e.pose = {0.4, 0, 0.2};
    e.mass = 5;
    e.shapes = {make_ellipse({0, 0}, 0.3, 0.15)};
    BodyId ell = add(w, e);
    const double e0 = w.kinetic_energy();
    const Vec2 p0 = w.linear_momentum();
    const double l0 = w.angular_momentum({0.2, -0.3});
    const Twist ball_before = w.velocity(ball);
    run(w, 0.5);
    EXPECT_NE(w.velocity(ball), ball_before) << "no impact happened (f=" << f << ")";
    EXPECT_NE(w.velocity(ell).w, 0.0) << "an off-centre impact spins the ellipse (f=" << f << ")";
    EXPECT_LT(w.kinetic_energy(), e0) << "f=" << f;
    EXPECT_NEAR(w.linear_momentum().x, p0.x, 1e-9) << "f=" << f;
    EXPECT_NEAR(w.linear_momentum().y, p0.y, 1e-9) << "f=" << f;
    EXPECT_NEAR(w.angular_momentum({0.2, -0.3}), l0, 1e-9) << "f=" << f;
  }
}

TEST(Bounce, NormalSpeedAfterAWallIsRestitutionTimesBefore) {
  for (double e : {0.0, 0.3, 0.5, 0.8, 1.0}) {
    World w(settings(e, 0.3));
    BodyId ball = add(w, ball_def({0, 0}, {2.5, 0}));
    add(w, wall_def({1.5, 0}, 0.1, 4));
    run(w, 1.0);
    EXPECT_NEAR(w.velocity(ball).vx, -e * 2.5, 1e-9) << "e=" << e;
    EXPECT_NEAR(w.velocity(ball).vy, 0, 1e-12);
    EXPECT_LE(w.pose(ball).x, 1.45 - kBallRadius + 1e-9) << "the ball stays on its side";
  }
}

TEST(Bounce, SpeedsBetweenTwoWallsFallAsPowersOfRestitution) {
  // The planar analogue of a ball's bounce heights: every bounce keeps the
  // fraction e of the speed, so after n bounces it is e^n v0.
  const double e = 0.8, v0 = 5;
  World w(settings(e, 0));
  BodyId ball = add(w, ball_def({0, 0}, {v0, 0}));
  add(w, wall_def({1.05, 0}, 0.1, 2));
  add(w, wall_def({-1.05, 0}, 0.1, 2));
  int bounces = 0;
  double speed = v0;
  for (int i = 0; i < 400 && bounces < 6; ++i) {
    w.step();
    for (const ContactEvent& c : w.contacts()) {
      ASSERT_NEAR(c.approach_speed, speed, 1e-9 * v0) << "bounce " << bounces;
      speed *= e;
      ++bounces;
      EXPECT_NEAR(std::fabs(w.velocity(ball).vx), speed, 1e-9 * v0);
    }
  }
  EXPECT_EQ(bounces, 6);
}

TEST(Bounce, FrictionInterpolatesBetweenSlidingAndRolling) {
  // 45 degree impact on a wall. f = 0 keeps the tangential speed and gives
  // no spin; f = 1 leaves the contact point without tangential slip.
  for (double f : {0.0, 0.4, 1.0}) {
    World w(settings(0.6, f));
    BodyId ball = add(w, ball_def({0, 0}, {2, 2}));
    add(w, wall_def({1.5, 0}, 0.1, 10));
    run(w, 1.0);
    const Twist v = w.velocity(ball);
    EXPECT_NEAR(v.vx, -0.6 * 2, 1e-9) << "f=" << f;
    // Slip of the contact point (on the ball's +x side): vy + w * r.
    const double slip = v.vy + v.w * kBallRadius;
    // The contact point lies mid-gap (within the contact slop) of the
    // surface, which shifts the slip by about w * slop / 2.
    EXPECT_NEAR(slip, (1 - f) * 2, 2e-3) << "f=" << f;
    if (f == 0) {
      EXPECT_NEAR(v.vy, 2, 1e-12);
      EXPECT_NEAR(v.w, 0, 1e-12);
    }
  }
}

TEST(Tunnelling, TwentyMetresPerSecondDoNotPassATwoCentimetreWall) {
  // 0.1 s cycles: the ball would move 2 m in a step, 100 times the wall.
  for (double cycle : {0.1, 0.01}) {
    World w(settings(0.5, 0.2, cycle));
    BodyId ball = add(w, ball_def({-1, 0.3}, {20, 0}));
    add(w, wall_def({0, 0}, 0.02, 3));
    run(w, 1.0);
    EXPECT_LT(w.pose(ball).x, -0.01 - kBallRadius + 1e-6) << "cycle " << cycle;
    EXPECT_NEAR(w.velocity(ball).vx, -10, 1e-9) << "cycle " << cycle;
  }
  // A small fast polygon against a thin turned wall does not pass either.
  World w(settings(0.5, 0.2, 0.1));
  BodyDef puck;
  puck.pose = {-1, -1, 0};
  puck.velocity = {20, 20, 3};
  puck.mass = 0.2;
  puck.shapes = {make_rect({0, 0}, 0.03, 0.03)};
  BodyId p = add(w, puck);
  BodyDef wall = wall_def({0, 0}, 0.02, 4);
  wall.pose.a = kPi / 4;  // its thin side faces the puck
  add(w, wall);
  run(w, 0.5);
  const Vec2 at = w.pose(p).position();
  EXPECT_LT(at.x + at.y, 0) << "the puck stays on its side of the diagonal wall";
}

TEST(Heights, ABallPassesUnderAHighBodyAndHitsALowOne) {
  World w(settings(1.0, 0));
  BodyId ball = add(w, ball_def({-1, 0}, {2, 0}));
  BodyDef arch = wall_def({0, 0}, 0.2, 1);
  arch.shapes[0] = with_height(arch.shapes[0], 0.3, 0.8);  // above the ball's 0.22 m
  add(w, arch);
  run(w, 1.0);
  EXPECT_NEAR(w.velocity(ball).vx, 2, 1e-12);
  EXPECT_GT(w.pose(ball).x, 0.5);

  World w2(settings(1.0, 0));
  BodyId ball2 = add(w2, ball_def({-1, 0}, {2, 0}));
  BodyDef skirt = wall_def({0, 0}, 0.2, 1);
  skirt.shapes[0] = with_height(skirt.shapes[0], 0.2, 0.8);  // overlaps the top of the ball
  add(w2, skirt);
  run(w2, 1.0);
  EXPECT_NEAR(w2.velocity(ball2).vx, -2, 1e-9);
}

TEST(Overlaps, TeleportedBodiesArePushedApart) {
  World w(settings(0.5, 0.2));
  BodyDef a;
  a.mass = 10;
  a.shapes = {make_rect({0, 0}, 0.5, 0.5)};
  BodyId ia = add(w, a);
  a.pose = {0.3, 0.05, 0.2};
  BodyId ib = add(w, a);
  ASSERT_LT(w.distance(ia, ib).distance, -0.1);
  w.step();
  EXPECT_GE(w.distance(ia, ib).distance, -w.settings().contact_slop * 0.1);
  // Equal masses share the push and keep the centre of mass still.
  EXPECT_NEAR(w.center_of_mass(ia).x + w.center_of_mass(ib).x, 0.3, 1e-9);
}

TEST(Contacts, ABoxDrivenIntoAWallStaysOutOfIt) {
  World w(settings(0.3, 0.5));
  BodyDef robot;
  robot.mass = 20;
  robot.pose = {0, 0, 0.2};
  robot.shapes = {make_rect({0, 0}, 0.45, 0.4), with_height(make_rect({0.25, 0}, 0.05, 0.3), 0, 0.1)};
  BodyId r = add(w, robot);
  BodyId wall = add(w, wall_def({0.8, 0}, 0.1, 3));
  for (int i = 0; i < 300; ++i) {
    // A motion controller insists on 1 m/s into the wall every cycle.
    w.set_origin_velocity(r, {std::cos(w.pose(r).a), std::sin(w.pose(r).a), 0});
    w.step();
    ASSERT_GE(w.distance(r, wall).distance, -w.settings().contact_slop * 0.2) << "step " << i;
  }
}

TEST(Determinism, TheSameSceneHashesTheSame) {
  auto scene = [] {
    World w(settings(0.7, 0.3));
    for (int i = 0; i < 6; ++i) add(w, ball_def({-2.0 + 0.5 * i, 0.1 * i}, {3.0 - i, 1.0 * (i % 3) - 1}));
    add(w, wall_def({2.5, 0}, 0.1, 6));
    add(w, wall_def({-2.5, 0}, 0.1, 6));
    add(w, wall_def({0, 1.5}, 6, 0.1));
    add(w, wall_def({0, -1.5}, 6, 0.1));
    run(w, 5.0);
    return w.state_hash();
  };
  EXPECT_EQ(scene(), scene());
}

TEST(Handles, StaleHandlesAreDetected) {
  World w;
  BodyId a = add(w, ball_def({0, 0}, {0, 0}));
  w.destroy_body(a);
  EXPECT_FALSE(w.valid(a));
  BodyId b = add(w, ball_def({1, 0}, {0, 0}));
  EXPECT_EQ(a.index, b.index) << "the slot is reused";
  EXPECT_FALSE(w.valid(a)) << "but the old handle stays dead";
  EXPECT_EQ(w.pose(a), Pose2{});
  std::string error;
  BodyDef empty;
  EXPECT_EQ(w.create_body(empty, error), kNoBody);
  EXPECT_NE(error.find("at least one shape"), std::string::npos);
}

}  // namespace
}  // namespace troupe::robocup
