// The two motion models and movable objects: a world's `physics` key, pucks
// (models with gripper_return 1) that the rigid model lets robots push and
// the kinematic model keeps as obstacles, walls that stop rigid bodies, and
// Stage's gripper catching, carrying and dropping a puck.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "host-sim/sim/loader.h"
#include "host-sim/sim/world.h"
#include "tests/sim/temp_dir.h"

namespace troupe::sim {
namespace {

// A 6 m x 4 m walled room, a robot at (-1, 0) facing +x with a laser along
// its heading and a gripper in front of it, and a puck ahead at (x, 0).
std::string room_world(const std::string& physics, double puck_x, const std::string& paddles = "open") {
  return (physics.empty() ? "" : "physics \"" + physics + "\"\n") + R"(resolution 0.02
interval_sim 100
define wall model ( obstacle_return 1 color "gray" )
wall ( pose [0 2.05 0 0] size [6.2 0.1] )
wall ( pose [0 -2.05 0 0] size [6.2 0.1] )
wall ( pose [3.05 0 0 0] size [0.1 4] )
wall ( pose [-3.05 0 0 0] size [0.1 4] )
define puck model ( size [0.1 0.1 0.1] gripper_return 1 fiducial_return 7 mass 0.5 )
position ( name "bot" pose [-1 0 0 0] size [0.4 0.4 0.2] mass 10
  velocity_bounds [-1 1 0 0 0 0 -90 90] acceleration_bounds [-10 10 0 0 0 0 -900 900]
  laser ( range_max 8 fov 0 samples 1 )
  gripper ( pose [0.3 0 0 0] size [0.2 0.2 0.1] paddle_state [")" +
         paddles + R"(" "down"] )
)
puck ( name "p" pose [)" +
         std::to_string(puck_x) +
         R"( 0 0 0] )
)";
}

std::unique_ptr<World> load(const std::string& text, world::Diagnostics& d, troupe::test::TempDir& dir,
                            uint64_t seed = 1) {
  return World::load(dir.write("t.world", text), seed, d);
}

TEST(Physics, UnknownModelIsALoadErrorWithFileAndLine) {
  troupe::test::TempDir dir;
  world::Diagnostics d;
  WorldDesc w;
  EXPECT_FALSE(load_world_file(dir.write("t.world", "resolution 0.1\nphysics \"bouncy\"\n"), w, d));
  ASSERT_TRUE(d.has_errors());
  EXPECT_NE(d.str().find("t.world:2"), std::string::npos) << d.str();
  EXPECT_NE(d.str().find("\"bouncy\""), std::string::npos) << d.str();
}

TEST(Pucks, BadPuckAndGripperValuesAreErrorsWithFileAndLine) {
  troupe::test::TempDir dir;
  world::Diagnostics d;
  WorldDesc w;
  EXPECT_FALSE(load_world_file(dir.write("t.world", R"(resolution 0.1
model ( gripper_return 1 mass -2 )
position ( gripper ( paddle_state ["ajar" "down"] ) )
)"),
                               w, d));
  EXPECT_NE(d.str().find("t.world:2"), std::string::npos) << d.str();
  EXPECT_NE(d.str().find("mass must be > 0"), std::string::npos) << d.str();
  EXPECT_NE(d.str().find("t.world:3"), std::string::npos) << d.str();
  EXPECT_NE(d.str().find("paddle_state"), std::string::npos) << d.str();
}

TEST(Pucks, AreNamedPuckNAndDoNotShiftUnnamedRobotsNames) {
  troupe::test::TempDir dir;
  world::Diagnostics d;
  WorldDesc w;
  ASSERT_TRUE(load_world_file(dir.write("t.world", R"(resolution 0.1
model ( pose [1 0 0 0] gripper_return 1 )
position ( pose [-1 0 0 0] )
model ( pose [2 0 0 0] gripper_return 1 )
)"),
                              w, d))
      << d.str();
  ASSERT_EQ(w.robots.size(), 3u);
  EXPECT_EQ(w.robots[0].name, "puck0");
  EXPECT_EQ(w.robots[1].name, "r0");
  EXPECT_EQ(w.robots[2].name, "puck1");
}

TEST(Physics, KinematicIsTheDefaultAndRigidIsChosenByKey) {
  troupe::test::TempDir dir;
  for (const auto& [key, want] :
       {std::pair{std::string(), Physics::Kinematic}, std::pair{std::string("kinematic"), Physics::Kinematic},
        std::pair{std::string("rigid"), Physics::Rigid}}) {
    world::Diagnostics d;
    auto w = load(room_world(key, 0), d, dir);
    ASSERT_TRUE(w) << d.str();
    EXPECT_EQ(w->desc().physics, want) << key;
  }
}

TEST(Pucks, LoadAsMovableObjectsThatCommandsDoNotMove) {
  troupe::test::TempDir dir;
  world::Diagnostics d;
  auto w = load(room_world("rigid", 1), d, dir);
  ASSERT_TRUE(w) << d.str();
  ASSERT_EQ(w->robot_count(), 2u);
  const RobotId p = *w->find_robot("p");
  EXPECT_TRUE(w->robot(p).puck);
  EXPECT_FALSE(w->robot(*w->find_robot("bot")).puck);
  EXPECT_TRUE(w->command(p, Command::velocity(1, 0, 1)));
  for (int i = 0; i < 10; ++i) w->step();
  EXPECT_DOUBLE_EQ(w->state(p).pose.x, 1.0);
  EXPECT_DOUBLE_EQ(w->state(p).pose.a, 0.0);
}

// Drives the robot at 0.5 m/s towards the puck for `steps` steps.
void drive(World& w, int steps, double speed = 0.5) {
  const RobotId bot = *w.find_robot("bot");
  w.command(bot, Command::velocity(speed, 0, 0));
  for (int i = 0; i < steps; ++i) w.step();
}

TEST(Pucks, RigidRobotsPushThemKinematicRobotsStallAtThem) {
  troupe::test::TempDir dir;
  world::Diagnostics d;
  auto rigid = load(room_world("rigid", 0), d, dir);
  auto kinematic = load(room_world("", 0), d, dir);
  ASSERT_TRUE(rigid && kinematic) << d.str();
  // 3 s at 0.5 m/s: the robot's front (x + 0.2) reaches the puck's back
  // (-0.05) after 1.5 s.
  drive(*rigid, 30);
  drive(*kinematic, 30);
  const RobotId bot = *rigid->find_robot("bot"), p = *rigid->find_robot("p");

  const Pose rp = rigid->state(p).pose, rb = rigid->state(bot).pose;
  EXPECT_GT(rp.x, 0.5) << "the rigid robot pushed the puck ahead of it";
  EXPECT_GT(rb.x, -0.1);
  EXPECT_GT(rp.x - rb.x, 0.2 + 0.05 - 0.01) << "and does not overlap it";

  const Pose kp = kinematic->state(p).pose, kb = kinematic->state(bot).pose;
  EXPECT_DOUBLE_EQ(kp.x, 0.0) << "a kinematic puck is an obstacle";
  EXPECT_LT(kb.x, -0.25 + 1e-9);
  EXPECT_TRUE(kinematic->state(bot).stalled);
}

TEST(Pucks, RigidWallsStopRobotsAndPucks) {
  troupe::test::TempDir dir;
  world::Diagnostics d;
  auto w = load(room_world("rigid", 0), d, dir);
  ASSERT_TRUE(w) << d.str();
  drive(*w, 200, 1.0);  // far longer than the room is wide
  const RobotId bot = *w->find_robot("bot"), p = *w->find_robot("p");
  // The wall's inner face is at x = 3.
  EXPECT_LT(w->state(p).pose.x + 0.05, 3.0);
  EXPECT_LT(w->state(bot).pose.x + 0.2, w->state(p).pose.x - 0.05 + 0.01);
  EXPECT_GT(w->state(p).pose.x, 2.5) << "the puck was pushed up to the wall";
  EXPECT_TRUE(w->state(bot).stalled || w->state(bot).pose.x > 2.0);
}

TEST(Pucks, RangersAndFiducialsSeeThem) {
  troupe::test::TempDir dir;
  for (const std::string physics : {"", "rigid"}) {
    world::Diagnostics d;
    auto w = load(room_world(physics, 1), d, dir);
    ASSERT_TRUE(w) << d.str();
    const RobotId bot = *w->find_robot("bot");
    const uint32_t laser = w->robot(bot).rangers.first;
    w->set_wanted({SensorKind::Ranger, laser}, true);
    w->refresh_sensors();
    // From the robot's centre at -1 to the puck's near face at 0.95.
    ASSERT_EQ(w->ranger(laser).ranges.size(), 1u);
    EXPECT_NEAR(w->ranger(laser).ranges[0], 1.95, 0.03) << physics;
  }
}

TEST(Gripper, CatchesCarriesAndDropsAPuck) {
  troupe::test::TempDir dir;
  for (const std::string physics : {"", "rigid"}) {
    world::Diagnostics d;
    // The puck's centre is 0.3 m ahead of the robot: inside the gripper.
    auto w = load(room_world(physics, -0.7), d, dir);
    ASSERT_TRUE(w) << d.str();
    const RobotId bot = *w->find_robot("bot"), p = *w->find_robot("p");
    ASSERT_EQ(w->robot(bot).grippers.count, 1u);
    const uint32_t g = w->robot(bot).grippers.first;
    EXPECT_FALSE(w->gripper(g).closed);
    w->set_gripper(g, true);
    w->step();
    ASSERT_TRUE(w->gripper(g).holding) << physics;
    EXPECT_EQ(w->gripper(g).held, p);
    // Turn half a circle and drive: the puck stays 0.3 m ahead.
    w->command(bot, Command::velocity(0, 0, kPi / 2));
    for (int i = 0; i < 20; ++i) w->step();
    drive(*w, 10);
    const Pose b = w->state(bot).pose, q = w->state(p).pose;
    EXPECT_NEAR(q.x, b.x + 0.3 * std::cos(b.a), 1e-9) << physics;
    EXPECT_NEAR(q.y, b.y + 0.3 * std::sin(b.a), 1e-9) << physics;
    EXPECT_LT(q.x, -1.2) << physics << ": carried away from where it was";
    w->set_gripper(g, false);
    w->step();
    EXPECT_FALSE(w->gripper(g).holding);
    const Pose dropped = w->state(p).pose;
    drive(*w, 5, -0.5);  // back off
    EXPECT_NEAR(w->state(p).pose.x, dropped.x, 1e-9) << physics << ": dropped where it was";
  }
}

TEST(Gripper, ClosingOnNothingHoldsNothingAndResetReleases) {
  troupe::test::TempDir dir;
  world::Diagnostics d;
  auto w = load(room_world("rigid", 1), d, dir);  // the puck is out of reach
  ASSERT_TRUE(w) << d.str();
  const uint32_t g = w->robot(*w->find_robot("bot")).grippers.first;
  w->set_gripper(g, true);
  w->step();
  EXPECT_TRUE(w->gripper(g).closed);
  EXPECT_FALSE(w->gripper(g).holding);

  auto near = load(room_world("rigid", -0.7, "closed"), d, dir);
  ASSERT_TRUE(near) << d.str();
  const uint32_t g2 = near->robot(*near->find_robot("bot")).grippers.first;
  EXPECT_TRUE(near->gripper(g2).closed) << "paddle_state \"closed\"";
  near->set_gripper(g2, false);
  near->step();
  near->set_gripper(g2, true);
  near->step();
  ASSERT_TRUE(near->gripper(g2).holding);
  drive(*near, 10);
  near->reset();
  EXPECT_FALSE(near->gripper(g2).holding);
  EXPECT_DOUBLE_EQ(near->state(*near->find_robot("p")).pose.x, -0.7);
}

TEST(Physics, RigidRunsAreDeterministic) {
  troupe::test::TempDir dir;
  world::Diagnostics d;
  auto a = load(room_world("rigid", 0.1), d, dir), b = load(room_world("rigid", 0.1), d, dir);
  ASSERT_TRUE(a && b) << d.str();
  for (World* w : {a.get(), b.get()}) {
    w->command(*w->find_robot("bot"), Command::velocity(0.8, 0, 0.3));
    for (int i = 0; i < 100; ++i) w->step();
  }
  for (RobotId i = 0; i < a->robot_count(); ++i) {
    EXPECT_EQ(a->state(i).pose.x, b->state(i).pose.x);
    EXPECT_EQ(a->state(i).pose.y, b->state(i).pose.y);
    EXPECT_EQ(a->state(i).pose.a, b->state(i).pose.a);
  }
}

}  // namespace
}  // namespace troupe::sim
