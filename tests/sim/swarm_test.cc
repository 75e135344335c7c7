// The main example, examples/worlds/swarm100.world: 100 robots aggregate (a)
// with in-process controllers and (b) driven over the wire by the
// swarm-clients example, one client connection per robot.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>

#include "host-sim/troupe_sim/runner.h"
#include "tests/support/build_tree.h"
#include "tests/support/child_process.h"

namespace troupe::sim {
namespace {

const std::string kWorld = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/swarm100.world";

// Mean distance from each robot to its nearest neighbour, m.
double mean_distance(const World& w) {
  double sum = 0;
  for (RobotId i = 0; i < w.robot_count(); ++i) {
    double nearest = 1e9;
    for (RobotId j = 0; j < w.robot_count(); ++j) {
      if (j == i) continue;
      nearest = std::min(
          nearest, std::hypot(w.state(i).pose.x - w.state(j).pose.x, w.state(i).pose.y - w.state(j).pose.y));
    }
    sum += nearest;
  }
  return sum / double(w.robot_count());
}

TEST(Swarm100, AggregatesWithInProcessControllers) {
  SimOptions o;
  o.world = kWorld;
  o.fast = true;
  o.plugin_path = {testing::kPluginDir};
  o.quit_time = 60;
  o.serve = false;
  Runner runner;
  world::Diagnostics d;
  std::string error;
  ASSERT_TRUE(runner.init(o, d, error)) << d.str() << error;
  EXPECT_EQ(d.items().size(), 0u) << d.str();
  ASSERT_EQ(runner.world().robot_count(), 100u);
  const double before = mean_distance(runner.world());
  ASSERT_EQ(runner.run(), 0);
  EXPECT_NEAR(runner.world().time(), 60.0, 1e-6);
  const double after = mean_distance(runner.world());
  EXPECT_LT(after, 0.6 * before) << before << " -> " << after;
  // Nobody went through a wall or another robot: every robot is still in
  // the arena.
  for (RobotId i = 0; i < runner.world().robot_count(); ++i) {
    EXPECT_LT(std::fabs(runner.world().state(i).pose.x), 10.0);
    EXPECT_LT(std::fabs(runner.world().state(i).pose.y), 10.0);
  }
}

TEST(Swarm100, AggregatesDrivenByOneClientPerRobot) {
  SimOptions o;
  o.world = kWorld;
  o.port = 0;
  o.no_ctrl = true;
  o.plugin_path = {testing::kPluginDir};
  // Paused: swarm-clients steps it in lockstep, so the result does not
  // depend on how fast this machine is.
  o.paused = true;
  Runner runner;
  world::Diagnostics d;
  std::string error;
  ASSERT_TRUE(runner.init(o, d, error)) << d.str() << error;
  std::thread sim([&] { runner.run(); });

  // The example program, as a user runs it.
  const std::string target = "127.0.0.1:" + std::to_string(runner.port());
  const auto run = troupe::testing::run_to_end({SWARM_CLIENTS, target, "--steps", "320"}, 120000);
  runner.request_stop();
  sim.join();
  const std::string& text = run.out;

  ASSERT_EQ(run.status, 0) << text << run.err;
  unsigned robots = 0, connections = 0;
  double before = 0, after = 0;
  ASSERT_EQ(std::sscanf(text.c_str(), "%u robots, %u connections; mean distance at the start %lf", &robots,
                        &connections, &before),
            3)
      << text;
  const size_t at = text.find("mean distance at the end");
  ASSERT_NE(at, std::string::npos) << text;
  ASSERT_EQ(std::sscanf(text.c_str() + at, "mean distance at the end %lf", &after), 1) << text;
  EXPECT_EQ(robots, 100u);
  EXPECT_EQ(connections, 101u);
  EXPECT_LT(after, 0.8 * before) << text;
  EXPECT_NE(text.find("100 of 100 robots decided at each of 320 steps"), std::string::npos) << text;
}

// troupe-sim end to end: the same world and --seed give byte-identical
// trajectory logs; another seed another log (wander turns at random).
TEST(TroupeSim, SameSeedSameLogBytes) {
  const std::string dir = ::testing::TempDir();
  const std::string world = dir + "/wander.world";
  {
    std::FILE* f = std::fopen(world.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs(R"(resolution 0.05
define arena model ( color "gray30" )
arena ( name "walls" size [ 8 8 ]
  block ( points 4 point[0] [0 0] point[1] [8 0] point[2] [8 0.1] point[3] [0 0.1] )
  block ( points 4 point[0] [0 7.9] point[1] [8 7.9] point[2] [8 8] point[3] [0 8] )
  block ( points 4 point[0] [0 0] point[1] [0.1 0] point[2] [0.1 8] point[3] [0 8] )
  block ( points 4 point[0] [7.9 0] point[1] [8 0] point[2] [8 8] point[3] [7.9 8] ) )
define bot position ( size [ 0.3 0.3 ] ctrl "wander"
  ranger ( sensor ( range [ 0 3 ] fov 180 samples 19 noise [ 0.0004 0.01 0 ] ) ) )
bot ( name "a" pose [ -2 -2 0 0 ] )
bot ( name "b" pose [ 2 -2 0 90 ] )
bot ( name "c" pose [ 2 2 0 180 ] )
bot ( name "d" pose [ -2 2 0 270 ] )
)",
               f);
    std::fclose(f);
  }
  auto run = [&](uint64_t seed, const std::string& log) {
    SimOptions o;
    o.world = world;
    o.fast = true;
    o.plugin_path = {testing::kPluginDir};
    o.quit_time = 60;
    o.serve = false;
    o.seed = seed;
    o.log = log;
    Runner runner;
    world::Diagnostics d;
    std::string error;
    EXPECT_TRUE(runner.init(o, d, error)) << d.str() << error;
    EXPECT_EQ(runner.run(), 0);
  };
  const std::string a = dir + "/wander_a.csv", b = dir + "/wander_b.csv", c = dir + "/wander_c.csv";
  run(7, a);
  run(7, b);
  run(8, c);
  auto slurp = [](const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    std::string text;
    char buf[65536];
    size_t n;
    while (f && (n = std::fread(buf, 1, sizeof buf, f)) > 0) text.append(buf, n);
    if (f) std::fclose(f);
    return text;
  };
  const std::string ta = slurp(a), tb = slurp(b), tc = slurp(c);
  EXPECT_EQ(std::count(ta.begin(), ta.end(), '\n'), 1 + 600 * 4);  // header, 600 steps x 4 robots
  EXPECT_TRUE(ta == tb);
  EXPECT_FALSE(ta == tc);
  for (const std::string& p : {world, a, b, c}) std::remove(p.c_str());
}

}  // namespace
}  // namespace troupe::sim
