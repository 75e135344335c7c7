// The game around the physics: kickers, the players' broadcast channel,
// and the console that starts and stops players at run time.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "host-sim/robocup/game/console.h"
#include "sim_fixture.h"

namespace troupe::robocup {
namespace {

std::unique_ptr<Simulation> kicker_world(const std::string& kicker_direction = "0") {
  std::string error;
  std::string robot = test::pioneer_block();
  robot.replace(robot.find("direction 0"), 11, "direction " + kicker_direction);
  auto sim = test::make_sim("ball ( deceleration 0 )\n" + test::robot("r", "blue", 0, 0, 0, robot), error);
  EXPECT_TRUE(sim) << error;
  return sim;
}

TEST(Kicker, AKickGivesATouchingBallAccelTimesContact) {
  auto sim = kicker_world();
  // The rest plate's front is at x = 0.25; the ball touches it.
  sim->place_ball({0.25 + 0.11 + 0.005, 0}, {});
  EXPECT_EQ(sim->kicker_state(0), "rest");
  sim->kick(0);
  sim->step();
  EXPECT_EQ(sim->kicker_state(0), "kick");
  EXPECT_NEAR(sim->ball().velocity.x, 300 * 0.02, 1e-9);
  EXPECT_NEAR(sim->ball().velocity.y, 0, 1e-9);
  // The plate returns after its hold time; a kick meanwhile does nothing.
  sim->kick(0);
  sim->run_for(0.2);
  EXPECT_EQ(sim->kicker_state(0), "kick");
  sim->run_for(0.1);
  EXPECT_EQ(sim->kicker_state(0), "rest");
}

TEST(Kicker, ABallOutOfReachIsNotKicked) {
  auto sim = kicker_world();
  sim->place_ball({1.0, 0}, {});
  sim->kick(0);
  sim->step();
  EXPECT_EQ(sim->kicker_state(0), "kick") << "the plate fires";
  EXPECT_EQ(sim->ball().velocity.x, 0) << "but the ball is too far";
}

TEST(Kicker, KicksAlongItsDirection) {
  auto sim = kicker_world("1.5707963267948966");
  sim->place_ball({0.25 + 0.11 + 0.005, 0}, {});
  sim->kick(0);
  sim->step();
  EXPECT_NEAR(sim->ball().velocity.x, 0, 1e-9);
  EXPECT_NEAR(sim->ball().velocity.y, 6, 1e-9);
}

// The simulation runs on the one engine: its robots are the ball and the
// RoboCup robots, whose states follow the bodies the game layer moves.
TEST(OneWorld, TheEnginesRobotsAreTheBallAndTheRobotsAndFollowTheGame) {
  auto sim = kicker_world();
  sim::World& engine = sim->engine();
  ASSERT_EQ(engine.robot_count(), 2u);
  EXPECT_EQ(engine.robot(0).name, "ball");
  EXPECT_EQ(engine.robot(1).name, "r");
  EXPECT_EQ(engine.rigid(), &sim->physics());
  EXPECT_EQ(engine.rigid_body(0), sim->ball_body());
  EXPECT_EQ(engine.rigid_body(1), sim->robot_body(0));
  // A teleport shows at once; a kicked ball's motion after the cycle.
  sim->place_ball({0.25 + 0.11 + 0.005, 0}, {});
  EXPECT_EQ(engine.state(0).pose.x, 0.25 + 0.11 + 0.005);
  sim->place_robot(0, {0, 0.5, 1});
  EXPECT_EQ(engine.state(1).pose.y, 0.5);
  sim->place_robot(0, {0, 0, 0});
  sim->kick(0);
  sim->step();
  EXPECT_EQ(engine.state(0).pose.x, sim->ball().position.x);
  EXPECT_NEAR(engine.state(0).velocity.x, 300 * 0.02, 1e-9);
  EXPECT_EQ(engine.steps(), 1u);
}

TEST(Broadcast, PlayersHearEachOtherAndTheNearestChases) {
  std::string error;
  const std::string drive = "  motion_plugin ( plugin \"diff_drive\" )\n";
  auto sim = test::make_sim(
      "ball ( pose [-1 1 0 0] deceleration 100 )\n" +
          test::robot(
              "near", "blue", -1.6, 1, 0,
              test::pioneer_block(drive) + "  player ( plugin \"field_player\" home_x -3 home_y 1 )\n") +
          test::robot(
              "far", "blue", -3, -1.5, 0,
              test::pioneer_block(drive) + "  player ( plugin \"field_player\" home_x -3 home_y -1.5 )\n"),
      error);
  ASSERT_TRUE(sim) << error;
  sim->step();
  ASSERT_EQ(sim->broadcasts().size(), 2u);
  EXPECT_EQ(sim->broadcasts()[0].from, "near");
  EXPECT_EQ(sim->broadcasts()[0].data.rfind("ball 0.6", 0), 0u) << sim->broadcasts()[0].data;
  EXPECT_EQ(sim->broadcasts()[1].from, "far");
  const Vec2 far_start = sim->robot(1).pose.position();
  sim->run_for(2);
  EXPECT_LT(length(sim->robot(1).pose.position() - far_start), 0.05) << "the farther player keeps its spot";
  EXPECT_GT(length(sim->ball().position - Vec2{-1, 1}), 0.1) << "the nearer one went for the ball";
}

TEST(Console, StartsAndStopsPlayersAndReports) {
  std::string error;
  auto sim = test::make_sim(test::robot("r", "yellow", -2, 0, 3.14159,
                                        test::pioneer_block("  motion_plugin ( plugin \"diff_drive\" )\n")) +
                                "ball ( pose [-2.5 0 0 0] )\n",
                            error);
  ASSERT_TRUE(sim) << error;
  std::vector<std::string> out;
  Console console(*sim, [&out](const std::string& line) { out.push_back(line); });
  ASSERT_TRUE(console.execute_script("start r striker aim_y=0.3\nplayers\nrun 3\nscore\nstop r\nplayers\n",
                                     "script", error))
      << error;
  ASSERT_GE(out.size(), 4u);
  EXPECT_EQ(out[0], "started striker on r");
  EXPECT_EQ(out[1], "r striker");
  EXPECT_NE(out[2].find("goal yellow (blue 0 : yellow 1)"), std::string::npos) << out[2];
  EXPECT_EQ(out.back().rfind("score blue 0 yellow 1", 0), 0u) << out.back();
  EXPECT_EQ(sim->player_of(0), "");
  EXPECT_FALSE(console.execute_script("score\nfly r\n", "script", error));
  EXPECT_EQ(error,
            "script:2: fly: unknown command (run, step, reset, start, stop, score, state, players, problems, "
            "ball, place, kick, command, quit)");
  EXPECT_FALSE(console.execute_script("start nobody striker\n", "script", error));
  EXPECT_NE(error.find("script:1: start: expected `start ROBOT PLUGIN"), std::string::npos) << error;
  EXPECT_FALSE(console.execute_script("ball 1\n", "script", error));
  EXPECT_NE(error.find("expected `ball X Y [VX VY]`"), std::string::npos) << error;
}

}  // namespace
}  // namespace troupe::robocup

namespace troupe::robocup {
namespace {

TEST(Match, TheExampleMatchRepeatsExactlyForItsSeed) {
  auto run = [](uint64_t seed) {
    WorldSpec spec;
    std::string error;
    EXPECT_TRUE(load_world_file(TROUPE_SOURCE_DIR "/examples/robocup/match.world", spec, error)) << error;
    spec.seed = seed;
    auto sim = Simulation::create(std::move(spec), PluginLoader({test::kPluginDir}), error);
    EXPECT_TRUE(sim) << error;
    EXPECT_TRUE(sim->problems().empty());
    sim->run_for(5);
    const SensorReading& odometry = sim->readings(1)[0];
    return std::make_pair(sim->physics().state_hash(), odometry.odometry);
  };
  const auto a = run(2001), b = run(2001), c = run(7);
  EXPECT_EQ(a.first, b.first) << "same seed, same match";
  EXPECT_EQ(a.second, b.second);
  EXPECT_NE(a.second, c.second) << "another seed draws other sensor noise";
}

// The cycle times into the simulator's one Profile: its phases in pipeline
// order, one step counted per cycle, and the physics step's own phases
// nested inside the cycle's physics phase (their clock readings lie within
// its two), so they can never add up to more than it.
TEST(Profile, TimesEachPhaseOfEveryCycle) {
  auto sim = kicker_world();
  sim->place_ball({0.5, 0}, {2, 0});
  sim->run_for(0.5);
  const auto& cycle = sim->profile();
  std::vector<std::string> names;
  for (const auto& p : cycle.phases()) names.push_back(p.name);
  EXPECT_EQ(names,
            (std::vector<std::string>{"players", "motion", "kickers", "physics", "referee", "sensors"}));
  EXPECT_EQ(cycle.steps(), 50u);
  const auto& physics = sim->physics().profile();
  names.clear();
  for (const auto& p : physics.phases()) names.push_back(p.name);
  EXPECT_EQ(names, (std::vector<std::string>{"floor", "overlap", "impacts"}));
  EXPECT_EQ(physics.steps(), 50u);
  EXPECT_LE(physics.total_ns(), cycle.phases()[3].total_ns);

  // What --profile prints, in the Stage engine's table format.
  const std::string table = sim->profile_table();
  EXPECT_NE(table.find("(50 steps)"), std::string::npos) << table;
  EXPECT_NE(table.find("physics, by phase:\nphase "), std::string::npos) << table;
  EXPECT_NE(table.find("\nimpacts "), std::string::npos) << table;
}

}  // namespace
}  // namespace troupe::robocup
