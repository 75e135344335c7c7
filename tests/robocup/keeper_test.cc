// Goalkeeper policies, each by what it does: as pure decisions and as a
// robot in the simulation; and the benchmark harness built on them.
#include <gtest/gtest.h>

#include <set>

#include "host-sim/robocup/bench/goalkeeper_bench.h"
#include "host-sim/robocup/plugins/goalkeeper/keeper_policy.h"
#include "sim_fixture.h"

namespace troupe::robocup {
namespace {

using plugins::KeeperGeometry;
using plugins::KeeperMemory;
using plugins::KeeperPolicy;
using plugins::KeeperSettings;

// ---- Decisions ---------------------------------------------------------------

TEST(KeeperPolicy, BlockStandsOnTheLineFromBallToGoalCentre) {
  KeeperGeometry g;  // blue: goal line at -4.5, keeper line 0.35 in front
  EXPECT_NEAR(plugins::block_y(g, {-2.0, 1.0}), 1.0 * 0.35 / 2.5, 1e-12);
  EXPECT_NEAR(plugins::block_y(g, {-2.0, -1.0}), -0.14, 1e-12);
  EXPECT_NEAR(plugins::block_y(g, {-4.4, 2.0}), g.reach, 1e-12) << "clamped to its reach";
}

TEST(KeeperPolicy, InterceptAimsAtWhereTheBallCrossesItsLine) {
  KeeperGeometry g;
  double y = 0;
  ASSERT_TRUE(plugins::crossing_y(g, {-1.0, 1.0}, {-3.5, -1.0}, y));
  EXPECT_NEAR(y, 1.0 - 1.0 * (4.15 - 1.0) / 3.5, 1e-12);
  EXPECT_FALSE(plugins::crossing_y(g, {-1.0, 1.0}, {3.5, 0}, y)) << "rolling away";
  EXPECT_FALSE(plugins::crossing_y(g, {-1.0, 1.0}, {-1.0, 2.0}, y)) << "going wide of the goal";
}

TEST(KeeperPolicy, EachPolicyDecidesAsDocumented) {
  KeeperGeometry g;
  KeeperSettings s;
  Rng rng(3);
  KeeperMemory m;
  const Vec2 me{-4.0, 0.3}, ball{-2, 1}, rolling{-3, -0.5};
  EXPECT_EQ(plugins::keeper_target(KeeperPolicy::None, g, s, me, ball, {}, 0, m, rng), me);
  // Random: a new spot every period, within reach, repeatable by seed.
  std::set<double> spots;
  for (double t = 0; t < 10; t += 0.25) {
    const Vec2 p = plugins::keeper_target(KeeperPolicy::Random, g, s, me, ball, {}, t, m, rng);
    EXPECT_EQ(p.x, g.line_x());
    EXPECT_LE(std::fabs(p.y), g.reach);
    spots.insert(p.y);
  }
  EXPECT_EQ(spots.size(), 10u) << "one spot per second";
  // Pattern: centre, one post, centre, the other post.
  KeeperMemory pm;
  EXPECT_NEAR(plugins::keeper_target(KeeperPolicy::Pattern, g, s, me, ball, {}, 0, pm, rng).y, 0, 1e-12);
  EXPECT_NEAR(plugins::keeper_target(KeeperPolicy::Pattern, g, s, me, ball, {}, 1, pm, rng).y, g.reach,
              1e-12);
  EXPECT_NEAR(plugins::keeper_target(KeeperPolicy::Pattern, g, s, me, ball, {}, 3, pm, rng).y, -g.reach,
              1e-12);
  // Intercept falls back to blocking when nothing comes at the goal.
  KeeperMemory im;
  plugins::keeper_target(KeeperPolicy::Intercept, g, s, me, ball, {0, 0}, 0, im, rng);
  EXPECT_EQ(im.acting, KeeperPolicy::Block);
  plugins::keeper_target(KeeperPolicy::Intercept, g, s, me, ball, rolling, 0, im, rng);
  EXPECT_EQ(im.acting, KeeperPolicy::Intercept);
  // Mixed: switches among the moving policies, the same way for a seed.
  auto mix = [&](uint64_t seed) {
    Rng r(seed);
    KeeperMemory mm;
    std::vector<KeeperPolicy> used;
    for (double t = 0; t < 40; t += 2) {
      plugins::keeper_target(KeeperPolicy::Mixed, g, s, me, ball, rolling, t, mm, r);
      used.push_back(mm.acting);
    }
    return used;
  };
  const auto used = mix(5);
  EXPECT_EQ(used, mix(5));
  EXPECT_NE(used, mix(6));
  EXPECT_GE(std::set<KeeperPolicy>(used.begin(), used.end()).size(), 3u);
}

// ---- In the simulation --------------------------------------------------------

std::unique_ptr<Simulation> keeper_world(const std::string& policy, uint64_t seed = 1,
                                         double ball_deceleration = 100, const std::string& more = "") {
  std::string error;
  auto sim = test::make_sim("seed " + std::to_string(seed) + "\nball ( pose [-2 1.5 0 0] deceleration " +
                                std::to_string(ball_deceleration) + " )\n" +
                                test::robot("k", "blue", -4.15, 0, 0,
                                            "  shape ( kind \"ellipse\" rx 0.18 ry 0.25 z [0 0.5] )\n"
                                            "  motion_plugin ( plugin \"omni_drive\" radius 0.17 wheel_speed 2.5 "
                                            "wheel_accel 8 )\n"
                                            "  player ( plugin \"goalkeeper\" latency 0 policy \"" +
                                                policy + "\" " + more + " )\n"),
                            error);
  EXPECT_TRUE(sim) << error;
  if (sim) {
    EXPECT_TRUE(sim->problems().empty()) << sim->problems()[0];
  }
  return sim;
}

std::vector<Vec2> track(Simulation& sim, double seconds) {
  std::vector<Vec2> out;
  const long n = std::lround(seconds / sim.cycle_s());
  for (long i = 0; i < n; ++i) {
    sim.step();
    out.push_back(sim.robot(0).pose.position());
  }
  return out;
}

TEST(Goalkeeper, NoneStandsStill) {
  auto sim = keeper_world("none");
  sim->place_ball({-2, 0}, {-4, 0.5});
  for (Vec2 p : track(*sim, 0.3)) {
    EXPECT_NEAR(p.x, -4.15, 1e-9);
    EXPECT_NEAR(p.y, 0, 1e-9);
  }
}

TEST(Goalkeeper, RandomWandersRepeatablyBySeed) {
  auto a = keeper_world("random", 1), b = keeper_world("random", 1), c = keeper_world("random", 2);
  const auto ta = track(*a, 6), tb = track(*b, 6), tc = track(*c, 6);
  EXPECT_EQ(ta.back(), tb.back());
  EXPECT_NE(ta.back(), tc.back());
  double lo = 0, hi = 0;
  for (Vec2 p : ta) {
    lo = std::min(lo, p.y);
    hi = std::max(hi, p.y);
    EXPECT_NEAR(p.x, -4.15, 0.05) << "it stays on its line";
  }
  EXPECT_GT(hi - lo, 0.5) << "it covers ground";
}

TEST(Goalkeeper, PatternSweepsPostToPost) {
  auto sim = keeper_world("pattern");
  double lo = 0, hi = 0;
  for (Vec2 p : track(*sim, 4.5)) {
    lo = std::min(lo, p.y);
    hi = std::max(hi, p.y);
  }
  EXPECT_NEAR(hi, 0.8, 0.1);
  EXPECT_NEAR(lo, -0.8, 0.1);
}

TEST(Goalkeeper, BlockFollowsTheBallOnItsLineToTheGoal) {
  auto sim = keeper_world("block");
  track(*sim, 2);
  EXPECT_NEAR(sim->robot(0).pose.y, 1.5 * 0.35 / 2.5, 0.02);
  sim->place_ball({-3, -1.2}, {});
  track(*sim, 2);
  EXPECT_NEAR(sim->robot(0).pose.y, -1.2 * 0.35 / 1.5, 0.02);
}

TEST(Goalkeeper, InterceptMeetsARollingBallThatBlockingMisses) {
  // A ball from the right wing aimed at the far post.
  auto outcome = [](const std::string& policy) {
    auto sim = keeper_world(policy, 1, 0.4);
    sim->place_ball({-1.5, 1.8}, {});
    track(*sim, 1);  // settle
    const Vec2 from{-1.5, 1.8}, to{-4.5, -0.85};
    sim->place_ball(from, normalized(to - from) * 5);
    int goals = 0;
    for (int i = 0; i < 150; ++i) {
      sim->step();
      for (const RefereeEvent& e : sim->events()) goals += e.kind == RefereeEventKind::Goal;
    }
    return goals;
  };
  EXPECT_EQ(outcome("block"), 1);
  EXPECT_EQ(outcome("intercept"), 0);
}

TEST(Goalkeeper, MixedFollowsNoSinglePolicyButRepeats) {
  auto run = [](const std::string& policy, uint64_t seed) {
    auto sim = keeper_world(policy, seed, 100, "mix_period 1");
    return track(*sim, 8);
  };
  const auto mixed = run("mixed", 4);
  EXPECT_EQ(mixed, run("mixed", 4));
  for (const char* pure : {"block", "pattern", "random", "intercept"}) {
    EXPECT_NE(mixed, run(pure, 4)) << pure;
  }
}

// ---- The benchmark ---------------------------------------------------------------

TEST(GoalkeeperBench, EveryPolicyFacesTheSameShotsAndTheTableAddsUp) {
  WorldSpec world;
  std::string error;
  ASSERT_TRUE(parse_world_text(standard_bench_world(), "std", world, error)) << error;
  BenchSettings s;
  s.shots = 12;
  s.seeds = {1};
  s.policies = {"none", "intercept"};
  s.plugin_path = {test::kPluginDir};
  std::vector<BenchCell> cells, again;
  ASSERT_TRUE(run_goalkeeper_bench(world, s, cells, error)) << error;
  ASSERT_TRUE(run_goalkeeper_bench(world, s, again, error)) << error;
  ASSERT_EQ(cells.size(), 2u);
  for (size_t i = 0; i < cells.size(); ++i) {
    const BenchCell& c = cells[i];
    EXPECT_EQ(c.shots, 12);
    EXPECT_EQ(c.goals + c.saves + c.misses + c.no_kick, c.shots);
    EXPECT_EQ(c.no_kick, 0) << "the scripted striker always gets its shot off";
    EXPECT_EQ(c.goals, again[i].goals) << "the same seed gives the same table";
  }
  EXPECT_GT(cells[0].goals, cells[1].goals)
      << "a keeper that intercepts concedes less than one standing still";
  EXPECT_EQ(shot_setups(s, world.field, 1)[3].ball, shot_setups(s, world.field, 1)[3].ball);
  char* text = nullptr;
  size_t size = 0;
  FILE* out = open_memstream(&text, &size);
  print_bench_table(cells, s, out);
  fclose(out);
  const std::string table(text, size);
  free(text);
  EXPECT_NE(table.find("intercept       1     12"), std::string::npos) << table;
  EXPECT_NE(table.find("none          all     12"), std::string::npos) << table;
}

TEST(GoalkeeperBench, AWorldWithoutTheRobotsIsAClearError) {
  WorldSpec world;
  BenchSettings s;
  s.plugin_path = {test::kPluginDir};
  std::vector<BenchCell> cells;
  std::string error;
  EXPECT_FALSE(run_goalkeeper_bench(world, s, cells, error));
  EXPECT_EQ(error, "the world needs robots named 'keeper' and 'striker'");
}

}  // namespace
}  // namespace troupe::robocup
