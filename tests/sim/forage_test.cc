// The foraging example, examples/worlds/forage.world: 50 robots on rigid-body
// physics gather pucks into the nest with their grippers. Against the
// control case (the same world, seed and steps with no controller running)
// the nest gains many pucks, and the same seed gathers the same ones.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "host-sim/sim/controller_host.h"
#include "host-sim/sim/world.h"
#include "tests/support/build_tree.h"

namespace troupe::sim {
namespace {

const std::string kWorld = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/forage.world";
constexpr double kNestHalf = 1.5;  // m: the nest model's half width in forage.world
constexpr int kSteps = 900;        // 90 s simulated

struct Outcome {
  int in_nest = 0;
  std::vector<double> xs;  // every puck's final x, m
};

int pucks_in_nest(const World& w) {
  int n = 0;
  for (RobotId i = 0; i < w.robot_count(); ++i) {
    const Pose& p = w.state(i).pose;
    if (w.robot(i).puck && std::fabs(p.x) < kNestHalf && std::fabs(p.y) < kNestHalf) ++n;
  }
  return n;
}

Outcome run(bool controllers, uint64_t seed) {
  world::Diagnostics d;
  auto w = World::load(kWorld, seed, d);
  EXPECT_TRUE(w) << d.str();
  if (!w) return {};
  EXPECT_EQ(w->desc().physics, Physics::Rigid);
  ControllerHost host;
  if (controllers) {
    ControllerHost::Options o;
    o.search_path = {testing::kPluginDir};
    EXPECT_TRUE(host.load(*w, o, d)) << d.str();
    EXPECT_EQ(host.size(), 50u);
  }
  EXPECT_EQ(pucks_in_nest(*w), 0) << "the nest starts empty";
  for (int i = 0; i < kSteps; ++i) {
    host.update(*w);
    w->step();
  }
  EXPECT_TRUE(host.take_errors().empty());
  Outcome out;
  out.in_nest = pucks_in_nest(*w);
  for (RobotId i = 0; i < w->robot_count(); ++i) {
    if (w->robot(i).puck) out.xs.push_back(w->state(i).pose.x);
  }
  return out;
}

TEST(Forage, RobotsGatherPucksIntoTheNest) {
  const Outcome idle = run(false, 5), forage = run(true, 5);
  ASSERT_EQ(forage.xs.size(), 100u);
  std::printf("pucks in the nest after %d steps: %d foraging, %d idle\n", kSteps, forage.in_nest,
              idle.in_nest);
  EXPECT_EQ(idle.in_nest, 0);
  EXPECT_GE(forage.in_nest, 25) << "of 100 pucks after " << kSteps << " steps";
  EXPECT_GE(forage.in_nest, idle.in_nest + 25);
  const Outcome again = run(true, 5);
  EXPECT_EQ(again.in_nest, forage.in_nest);
  EXPECT_EQ(again.xs, forage.xs) << "same seed, same run";
}

}  // namespace
}  // namespace troupe::sim
