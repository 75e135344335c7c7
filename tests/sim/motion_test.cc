// The position model: drives, bounds, odometry, goto and power; and
// collisions: robots stop and stall at walls and at each other, never pass.
#include <gtest/gtest.h>

#include <cmath>

#include "host-sim/sim/world.h"
#include "tests/sim/scenes.h"

namespace troupe::sim {
namespace {

constexpr double kDeg = kPi / 180;

WorldDesc open_field() {
  return test::room(20, 20, 0.05);
}

void run(World& w, int steps) {
  for (int i = 0; i < steps; ++i) w.step();
}

TEST(Kinematics, DiffDriveFollowsTheExactArc) {
  WorldDesc d = open_field();
  d.robots.push_back(test::robot("r0", {0, 0, 0}));
  World w(d, Random(1));
  w.command(0, Command::velocity(0.5, 0.3, 0.5));  // y ignored by a diff drive
  run(w, 20);                                      // 2 s: heading 1 rad, radius 1 m
  const Pose& p = w.state(0).pose;
  EXPECT_NEAR(p.x, std::sin(1.0), 1e-9);
  EXPECT_NEAR(p.y, 1 - std::cos(1.0), 1e-9);
  EXPECT_NEAR(p.a, 1.0, 1e-9);
  EXPECT_NEAR(w.time(), 2.0, 1e-12);
  EXPECT_EQ(w.steps(), 20u);
  EXPECT_NEAR(w.state(0).velocity.x, 0.5, 1e-12);
  EXPECT_EQ(w.state(0).velocity.y, 0);
}

TEST(Kinematics, VelocityAndAccelerationBounds) {
  WorldDesc d = open_field();
  RobotDesc r = test::robot("r0", {0, 0, 0});
  r.velocity[0] = {-0.5, 0.5};
  r.velocity[2] = {-90 * kDeg, 90 * kDeg};
  r.acceleration[0] = {-0.5, 0.5};
  r.acceleration[2] = {-90 * kDeg, 90 * kDeg};
  d.robots.push_back(r);
  World w(d, Random(1));
  w.command(0, Command::velocity(2.0, 0, 10));
  w.step();
  EXPECT_NEAR(w.state(0).velocity.x, 0.05, 1e-12);  // 0.5 m/s^2 for 0.1 s
  EXPECT_NEAR(w.state(0).velocity.a, 9 * kDeg, 1e-12);
  run(w, 20);
  EXPECT_NEAR(w.state(0).velocity.x, 0.5, 1e-12);  // clamped to the bound
  EXPECT_NEAR(w.state(0).velocity.a, 90 * kDeg, 1e-12);
  w.command(0, Command::velocity(0, 0, 0));
  w.step();
  EXPECT_NEAR(w.state(0).velocity.x, 0.45, 1e-12);  // decelerates within the bound too
}

TEST(Kinematics, OmniMovesSidewaysAndCarSteers) {
  WorldDesc d = open_field();
  RobotDesc omni = test::robot("omni", {0, 0, 90 * kDeg});
  omni.drive = Drive::Omni;
  d.robots.push_back(omni);
  RobotDesc car = test::robot("car", {10, 0, 0});
  car.drive = Drive::Car;
  car.wheelbase = 2.0;
  d.robots.push_back(car);
  World w(d, Random(1));
  w.command(0, Command::velocity(0, 0.4, 0));    // left of a robot facing +y: -x
  w.command(1, Command::velocity(1.0, 0, 0.3));  // 1 m/s, steering 0.3 rad
  run(w, 10);
  EXPECT_NEAR(w.state(0).pose.x, -0.4, 1e-9);
  EXPECT_NEAR(w.state(0).pose.y, 0, 1e-9);
  const double turn = std::sin(0.3) / 2.0, speed = std::cos(0.3);
  EXPECT_NEAR(w.state(1).velocity.a, turn, 1e-12);
  EXPECT_NEAR(w.state(1).velocity.x, speed, 1e-12);
  EXPECT_NEAR(w.state(1).pose.a, turn * 1.0, 1e-9);
  EXPECT_NEAR(w.state(1).pose.x, 10 + speed / turn * std::sin(turn), 1e-9);
}

TEST(Kinematics, OdometryGpsAndOdomWithError) {
  WorldDesc d = open_field();
  RobotDesc gps = test::robot("gps", {1, 2, 30 * kDeg});
  gps.has_localization_origin = false;  // odometry frame = the start pose
  d.robots.push_back(gps);
  RobotDesc odom = test::robot("odom", {5, 5, 0});
  odom.localization = Localization::Odom;
  odom.has_localization_origin = false;
  odom.odom_error = {0.2, 0, 0};  // x scale error drawn in [-0.1, 0.1]
  d.robots.push_back(odom);
  World w(d, Random(42));
  w.command(0, Command::velocity(1, 0, 0));
  w.command(1, Command::velocity(1, 0, 0));
  run(w, 10);
  EXPECT_NEAR(w.state(0).odometry.x, 1.0, 1e-9);
  EXPECT_NEAR(w.state(0).odometry.y, 0.0, 1e-9);
  EXPECT_NEAR(w.state(1).pose.x, 6.0, 1e-9);
  const double err = w.state(1).odometry.x - 1.0;
  EXPECT_NE(err, 0.0);
  EXPECT_LE(std::fabs(err), 0.1 + 1e-12);
  // The error is the robot's own, drawn from the seed: the same again.
  World again(d, Random(42));
  again.command(1, Command::velocity(1, 0, 0));
  run(again, 10);
  EXPECT_EQ(again.state(1).odometry.x, w.state(1).odometry.x);
  // set_odometry restarts the estimate.
  w.set_odometry(1, {0, 0, 0});
  run(w, 1);
  EXPECT_NEAR(w.state(1).odometry.x, 0.1 * (1 + err), 1e-9);
}

TEST(Kinematics, GotoReachesTheGoal) {
  WorldDesc d = open_field();
  d.robots.push_back(test::robot("r0", {0, 0, 0}));
  World w(d, Random(1));
  w.command(0, Command::go_to(2, 1, 90 * kDeg));
  run(w, 300);
  const Pose& p = w.state(0).pose;
  EXPECT_NEAR(p.x, 2, 0.03);
  EXPECT_NEAR(p.y, 1, 0.03);
  EXPECT_NEAR(p.a, 90 * kDeg, 0.02);
}

TEST(Kinematics, AnEmptyBatteryStopsTheRobot) {
  WorldDesc d = open_field();
  RobotDesc r = test::robot("r0", {0, 0, 0});
  r.mass = 10;
  r.power = {true, 100, 100, 1.0};  // 100 J; 1 W plus 10 W/kg per m/s
  d.robots.push_back(r);
  World w(d, Random(1));
  w.command(0, Command::velocity(0.5, 0, 0));  // 51 W
  run(w, 19);
  EXPECT_NEAR(w.power(0).joules, 100 - 19 * 5.1, 1e-9);
  EXPECT_FALSE(w.state(0).disabled);
  run(w, 2);
  EXPECT_TRUE(w.state(0).disabled);
  const double x = w.state(0).pose.x;
  run(w, 5);
  EXPECT_EQ(w.state(0).pose.x, x);
}

TEST(Collision, ARobotStopsAtAWallAndStalls) {
  WorldDesc d = test::room(5, 3);
  d.robots.push_back(test::robot("r0", {0, 0, 0}, 0.4));
  World w(d, Random(1));
  w.command(0, Command::velocity(1.0, 0, 0));
  bool stalled = false;
  for (int i = 0; i < 100; ++i) {
    w.step();
    EXPECT_LE(w.state(0).pose.x + 0.2, 5.0) << "step " << i;
    stalled = stalled || w.state(0).stalled;
  }
  EXPECT_TRUE(stalled);
  EXPECT_TRUE(w.state(0).stalled);
  EXPECT_GT(w.state(0).pose.x + 0.2, 5.0 - 0.1);  // it got close first
  EXPECT_EQ(w.state(0).velocity.x, 0);
}

TEST(Collision, FastRobotsDoNotJumpThinWalls) {
  WorldDesc d = test::room(5, 3);
  d.statics[0].polygons.push_back(test::box(1.0, -3, 1.02, 3));  // one cell thick
  RobotDesc r = test::robot("r0", {0, 0, 0}, 0.1);
  d.robots.push_back(r);
  World w(d, Random(1));
  w.command(0, Command::velocity(8.0, 0, 0));  // 0.8 m per step
  run(w, 20);
  EXPECT_LT(w.state(0).pose.x, 1.0);
  EXPECT_TRUE(w.state(0).stalled);
}

TEST(Collision, WallsWithoutObstacleReturnLetRobotsThrough) {
  WorldDesc d = test::room(5, 3);
  StaticDesc ghost;
  ghost.size = {1, 10};
  ghost.polygons = {test::box(-0.05, -5, 0.05, 5)};
  ghost.pose = {1, 0, 0};
  ghost.look.obstacle = false;
  d.statics.push_back(ghost);
  d.robots.push_back(test::robot("r0", {0, 0, 0}, 0.2));
  World w(d, Random(1));
  w.command(0, Command::velocity(1.0, 0, 0));
  run(w, 20);
  EXPECT_NEAR(w.state(0).pose.x, 2.0, 1e-9);
  EXPECT_FALSE(w.state(0).stalled);
}

TEST(Collision, RobotsHeadOnStopWithoutOverlapping) {
  WorldDesc d = test::room(5, 3);
  d.robots.push_back(test::robot("a", {-1, 0.1, 0}, 0.4));
  d.robots.push_back(test::robot("b", {1, -0.1, kPi}, 0.4));
  d.robots.push_back(test::robot("c", {-1, 2, 0}, 0.4));  // passes by, never touched
  World w(d, Random(1));
  for (RobotId i = 0; i < 3; ++i) w.command(i, Command::velocity(0.7, 0, 0));
  for (int s = 0; s < 60; ++s) {
    w.step();
    auto oa = w.outline(0), ob = w.outline(1);
    ASSERT_FALSE(polygons_overlap(oa[0], ob[0])) << "step " << s;
  }
  EXPECT_TRUE(w.state(0).stalled);
  EXPECT_TRUE(w.state(1).stalled);
  EXPECT_LT(w.state(0).pose.x, w.state(1).pose.x);
  EXPECT_GT(w.state(0).pose.x, -0.5);  // they did close the gap
  EXPECT_FALSE(w.state(2).stalled);
}

TEST(Collision, BumperPressesOnTheSideThatHit) {
  WorldDesc d = test::room(5, 3);
  RobotDesc r = test::robot("r0", {4.0, 0, 0}, 0.4);
  BumperDesc b;
  b.segments = {{{0.2, 0, 0}, 0.3}, {{-0.2, 0, kPi}, 0.3}};  // front, back
  r.bumpers.push_back(b);
  d.robots.push_back(r);
  World w(d, Random(1));
  const uint32_t index = w.robot(0).bumpers.first;
  w.set_wanted({SensorKind::Bumper, index}, true);
  w.refresh_sensors();
  EXPECT_EQ(w.bumper(index).pressed, 0u);
  EXPECT_EQ(w.bumper(index).count, 2u);
  w.command(0, Command::velocity(0.5, 0, 0));
  run(w, 30);
  ASSERT_TRUE(w.state(0).stalled);
  EXPECT_EQ(w.bumper(index).pressed, 1u);  // the front one
}

TEST(World, ResetAndTeleport) {
  WorldDesc d = open_field();
  d.robots.push_back(test::robot("r0", {1, 1, 0}));
  World w(d, Random(1));
  w.command(0, Command::velocity(1, 0, 0));
  run(w, 5);
  w.set_pose(0, {-3, 4, 1});
  EXPECT_EQ(w.state(0).pose.x, -3);
  EXPECT_EQ(w.state(0).odometry.x, -3);  // gps in the world frame
  w.reset();
  EXPECT_EQ(w.state(0).pose.x, 1);
  EXPECT_EQ(w.steps(), 0u);
  EXPECT_EQ(w.time(), 0);
  EXPECT_EQ(w.state(0).velocity.x, 0);
  ASSERT_TRUE(w.find_robot("r0"));
  EXPECT_EQ(*w.find_robot("r0"), 0u);
  EXPECT_FALSE(w.find_robot("nobody"));
}

// Defence in depth: whatever reaches the world (a controller in process, an
// emulator, a path that skips the wire's checks), NaN and infinity are
// refused and the world stays finite and steppable.
TEST(Kinematics, NonFiniteInputsAreRefusedAndTheWorldStaysFinite) {
  WorldDesc d = open_field();
  d.robots.push_back(test::robot("r0", {1, 1, 0}));
  d.robots.push_back(test::robot("r1", {-5, -5, 0}));
  d.robots.back().localization = Localization::Odom;
  World w(d, Random(1));
  ASSERT_TRUE(w.command(0, Command::velocity(0.5, 0, 0)));
  const double nan = std::nan(""), inf = INFINITY;
  for (const Pose& bad : {Pose{nan, 0, 0}, Pose{0, inf, 0}, Pose{0, 0, -inf}, Pose{nan, nan, nan}}) {
    EXPECT_FALSE(w.command(0, Command::velocity(bad.x, bad.y, bad.a)));
    EXPECT_FALSE(w.command(1, Command::go_to(bad.x, bad.y, bad.a)));
    EXPECT_FALSE(w.set_pose(1, bad));
    EXPECT_FALSE(w.set_odometry(1, bad));
  }
  // Finite but beyond any map: refused too.
  EXPECT_FALSE(w.set_pose(1, {1e30, 0, 0}));
  EXPECT_FALSE(w.set_pose(1, {0, -2 * kMaxCoordinate, 0}));
  EXPECT_TRUE(w.set_pose(1, {kMaxCoordinate, -kMaxCoordinate, 0}));
  run(w, 10);
  // r0 kept its last good command; r1 far away stepped too.
  EXPECT_NEAR(w.state(0).pose.x, 1.5, 1e-9);
  EXPECT_NEAR(w.state(0).velocity.x, 0.5, 1e-12);
  for (RobotId r : {0u, 1u}) {
    const RobotState& s = w.state(r);
    EXPECT_TRUE(finite_pose(s.pose) && finite_pose(s.velocity) && finite_pose(s.odometry)) << r;
  }
  EXPECT_TRUE(w.set_pose(1, {2, 2, 0}));
  EXPECT_TRUE(w.set_odometry(1, {0, 0, 0}));
  EXPECT_EQ(w.state(1).pose.x, 2);
}

}  // namespace
}  // namespace troupe::sim
