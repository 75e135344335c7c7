// What a game layer builds on in a rigid world (RoboCup mode does): static
// rigid bodies that a ball bounces off by the world's restitution while rays
// still see them, undriven bodies that keep the velocity their owner gives
// them, the accessor to the same bodies, and states that follow teleports.
#include <gtest/gtest.h>

#include <cmath>

#include "host-sim/robocup/physics/world.h"
#include "host-sim/sim/world.h"

namespace troupe::sim {
namespace {

constexpr uint64_t kWallLabel = 77, kBallLabel = 5;

// A wall 0.2 m thick whose near face is at x = 1 (a static rigid body, and
// ranger-visible cells that are no obstacle), and a ball at the origin:
// robot 0, undriven, 0.1 m in radius, no floor friction.
WorldDesc wall_and_ball(double restitution) {
  WorldDesc w;
  w.physics = Physics::Rigid;
  w.interval_sim = 0.01;
  w.rigid.restitution = restitution;
  w.rigid.friction = 0;
  StaticDesc wall;
  wall.name = "wall";
  wall.pose = {1.1, 0, 0};
  wall.size = {0.2, 2};
  wall.polygons = {{{-0.1, -1}, {0.1, -1}, {0.1, 1}, {-0.1, 1}}};
  wall.look.obstacle = false;
  wall.rigid_shapes = {robocup::make_rect({0, 0}, 0.2, 2)};
  wall.rigid_user_data = kWallLabel;
  w.statics.push_back(wall);
  RobotDesc ball;
  ball.name = "ball";
  ball.puck = true;
  ball.size = {0.2, 0.2};
  ball.mass = 0.5;
  RigidDesc rigid;
  rigid.shapes = {robocup::make_circle({0, 0}, 0.1)};
  rigid.driven = false;
  rigid.user_data = kBallLabel;
  ball.rigid = rigid;
  w.robots.push_back(ball);
  return w;
}

// The ball's speed along x after it was sent at 2 m/s into the wall and
// had time to come back, m/s.
double rebound_speed(double restitution) {
  World world(wall_and_ball(restitution), Random(1));
  world.rigid()->set_velocity(world.rigid_body(0), {2, 0, 0});
  for (int i = 0; i < 100; ++i) world.step();  // 1 s: the wall is 0.9 m away
  EXPECT_LT(world.state(0).pose.x, 0.9);
  return world.state(0).velocity.x;
}

TEST(RigidBodies, ABallBouncesOffAStaticBodyByTheWorldsRestitution) {
  EXPECT_NEAR(rebound_speed(0.8), -1.6, 1e-6);
  EXPECT_NEAR(rebound_speed(0.3), -0.6, 1e-6);
}

TEST(RigidBodies, RaysSeeAStaticBodyTheGridDoesNotStopAt) {
  WorldDesc d = wall_and_ball(0.5);
  RobotDesc bot;
  bot.name = "bot";
  bot.pose = {0, 0.5, 0};
  bot.size = {0.2, 0.2};
  RangerDesc laser;
  TransducerDesc beam;
  beam.range_max = 5;
  laser.transducers.push_back(beam);
  bot.rangers.push_back(laser);
  d.robots.push_back(bot);
  World world(d, Random(1));
  world.set_wanted({SensorKind::Ranger, 0}, true);
  world.refresh_sensors();
  EXPECT_NEAR(world.ranger(0).ranges[0], 1.0, 0.03);  // the wall's face, to a cell
}

TEST(RigidBodies, AnUndrivenBodyKeepsItsOwnersVelocityADrivenOneFollowsItsCommand) {
  WorldDesc d = wall_and_ball(0.5);
  d.statics.clear();
  RobotDesc bot;
  bot.name = "bot";
  bot.pose = {0, 2, 0};
  bot.size = {0.2, 0.2};
  d.robots.push_back(bot);
  World world(d, Random(1));
  world.rigid()->set_velocity(world.rigid_body(0), {0.5, 0, 0});
  ASSERT_TRUE(world.command(0, Command::velocity(0, 0, 1)));  // not the ball's drive
  ASSERT_TRUE(world.command(1, Command::velocity(0.3, 0, 0)));
  for (int i = 0; i < 100; ++i) world.step();
  EXPECT_NEAR(world.state(0).pose.x, 0.5, 1e-9);
  EXPECT_NEAR(world.state(0).pose.a, 0, 1e-12);
  EXPECT_NEAR(world.state(0).velocity.x, 0.5, 1e-12);
  // Accelerating at 1 m/s^2 to 0.3 m/s takes 0.3 s: 0.045 m short of 0.3.
  EXPECT_NEAR(world.state(1).pose.x, 0.3 - 0.045, 0.01);
}

TEST(RigidBodies, TheAccessorGivesTheSameBodiesAndStatesFollowItsTeleports) {
  World world(wall_and_ball(0.5), Random(1));
  robocup::World& rigid = *world.rigid();
  EXPECT_EQ(rigid.user_data(world.rigid_static_body(0)), kWallLabel);
  EXPECT_EQ(rigid.user_data(world.rigid_body(0)), kBallLabel);
  EXPECT_FALSE(rigid.valid(world.rigid_static_body(1)));
  EXPECT_FALSE(rigid.valid(world.rigid_body(1)));
  rigid.set_pose(world.rigid_body(0), {-0.5, 0.25, 0});
  rigid.set_velocity(world.rigid_body(0), {0, 1, 0});
  EXPECT_EQ(world.state(0).pose.x, 0);  // until told
  world.rigid_moved();
  EXPECT_EQ(world.state(0).pose.x, -0.5);
  EXPECT_EQ(world.state(0).pose.y, 0.25);
  EXPECT_EQ(world.state(0).velocity.y, 1);
}

TEST(RigidBodies, AKinematicWorldHasNone) {
  WorldDesc d = wall_and_ball(0.5);
  d.physics = Physics::Kinematic;
  World world(d, Random(1));
  EXPECT_EQ(world.rigid(), nullptr);
  EXPECT_EQ(world.rigid_body(0), robocup::kNoBody);
  world.rigid_moved();  // nothing to take
  EXPECT_EQ(world.state(0).pose.x, 0);
}

}  // namespace
}  // namespace troupe::sim
