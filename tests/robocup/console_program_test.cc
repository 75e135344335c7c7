// troupe-sim with a RoboCup world, run from the console, and troupe-robocup,
// its alias (`troupe-sim --fast --no-serve` under another name, a symbolic
// link): the real programs, every test run through both. Scripts and
// standard input run commands between cycles; the referee's events and the
// final line go to standard output (--quiet drops the events); a bad
// command is reported with its line and changes nothing; --seed N seeds
// with N, 0 included; one exit rule (1 world, script or command, 2 command
// line).
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "tests/support/child_process.h"

namespace troupe::robocup {
namespace {

const std::string kBin = TROUPE_BINARY_DIR "/bin/";
const std::string kMatch = TROUPE_SOURCE_DIR "/examples/robocup/match.world";
const std::string kStageWorld = TROUPE_SOURCE_DIR "/examples/worlds/room.world";

// The alias is named by how it is started: both programs, one rule.
const std::vector<std::string> kPrograms = {kBin + "troupe-sim", kBin + "troupe-robocup"};

class ConsoleProgram : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    dir_ = testing::make_temp_dir("troupe-console");
    ASSERT_FALSE(dir_.empty());
  }
  void TearDown() override { testing::remove_tree(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    const std::string path = dir_ + "/" + name;
    std::ofstream(path) << text;
    return path;
  }
  // The program on `world`, with `args` after it; troupe-sim batch runs get
  // the alias's --fast --no-serve only where the test says so.
  testing::ProgramResult run(const std::string& world, std::vector<std::string> args) {
    args.insert(args.begin(), {GetParam(), world});
    return testing::run_to_end(args, 120000);
  }
  // With `input` on standard input (--interactive reads it).
  testing::ProgramResult run_typed(const std::string& input, const std::string& args) {
    const std::string in = write("typed.txt", input);
    return testing::run_to_end({"/bin/sh", "-c", "'" + GetParam() + "' " + args + " < '" + in + "'"}, 120000);
  }

  std::string dir_;
};

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST_P(ConsoleProgram, AScriptRunsBetweenCyclesWithEventsAndTheFinalLine) {
  const std::string script = write("goal.txt", "ball 4.8 0\nstep 2\nscore\n");
  const auto r = run(kMatch, {"--script", script});
  EXPECT_EQ(r.status, 0) << r.err;
  // The ball behind the yellow goal line: blue scores in the first cycle.
  EXPECT_TRUE(contains(r.out,
                       "t=0.010 goal blue (blue 1 : yellow 0)\n"
                       "score blue 1 yellow 0 phase goal-pause t=0.020\n"
                       "final: blue 1 yellow 0 after 0.02 s simulated in "))
      << r.out;

  // --quiet drops the event, not what a command was asked for.
  const auto quiet = run(kMatch, {"--script", script, "--quiet"});
  EXPECT_EQ(quiet.status, 0) << quiet.err;
  EXPECT_FALSE(contains(quiet.out, "goal blue")) << quiet.out;
  EXPECT_TRUE(contains(quiet.out,
                       "score blue 1 yellow 0 phase goal-pause t=0.020\n"
                       "final: blue 1 yellow 0 after 0.02 s simulated in "))
      << quiet.out;
}

TEST_P(ConsoleProgram, ABadScriptCommandStopsTheScriptWithItsLineAndChangesNothing) {
  const std::string script = write("bad.txt", "ball 1 1\nplace blue0 1 1\nstate\n");
  const auto r = run(kMatch, {"--script", script});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, script + ":2: place: expected `place ROBOT X Y A`")) << r.err;
  EXPECT_FALSE(contains(r.out, "robot blue0")) << "the script ran on after its error:\n" << r.out;
  EXPECT_TRUE(contains(r.out, "final: blue 0 yellow 0 after 0.00 s simulated")) << r.out;
}

TEST_P(ConsoleProgram, TypedCommandsGoOnAfterABadOneWhichChangesNothing) {
  // Lines 2, 4 and 5 are wrong: a bad number, an unknown command, a block.
  const auto r = run_typed("ball 1 1\nball 2 x\nstate\nfly blue0\nrun {\nstate\nquit\nball 3 3\n",
                           "'" + kMatch + "' --interactive");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(contains(r.err, "stdin:2: ball: expected `ball X Y [VX VY]`")) << r.err;
  EXPECT_TRUE(contains(r.err, "stdin:4: fly: unknown command")) << r.err;
  EXPECT_TRUE(contains(r.err, "stdin:5: '{': commands take no block")) << r.err;
  // Both `state`s see the ball where line 1 put it; `quit` ends the input.
  const std::string ball = "ball 1.000 1.000 v 0.000 0.000\n";
  const size_t first = r.out.find(ball);
  ASSERT_NE(first, std::string::npos) << r.out;
  EXPECT_NE(r.out.find(ball, first + 1), std::string::npos) << r.out;
  EXPECT_FALSE(contains(r.out, "ball 3.000")) << r.out;
  EXPECT_TRUE(contains(r.out, "final: blue 0 yellow 0 after 0.00 s simulated")) << r.out;
}

// Without a console the match runs on the paced loop (flat out and
// unserved here), and its events are printed as they happen all the same.
TEST_P(ConsoleProgram, ABatchRunPrintsTheRefereesEventsAndTheFinalLine) {
  const std::string world =
      write("goal.world",
            "robocup_field ( length 9 width 5 )\nball ( pose [4.8 0 0 0] )\nreferee ( goal_pause 1 )\n");
  const std::vector<std::string> batch = {"--fast", "--no-serve", "--quit-time", "0.5"};
  const auto r = run(world, batch);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(
      r.out.rfind("t=0.010 goal blue (blue 1 : yellow 0)\nfinal: blue 1 yellow 0 after 0.50 s simulated in ",
                  0),
      0u)
      << r.out;
  std::vector<std::string> quiet = batch;
  quiet.push_back("--quiet");
  const auto q = run(world, quiet);
  EXPECT_EQ(q.status, 0) << q.err;
  EXPECT_EQ(q.out.rfind("final: blue 1 yellow 0 after 0.50 s simulated in ", 0), 0u) << q.out;
}

// --seed N seeds the run with N, 0 included; without it the world's `seed`
// (2001 in match.world) does. The match's sensors are noisy, so the seed
// shows in where the robots are after a second.
TEST_P(ConsoleProgram, SeedZeroIsASeedAndNoSeedIsTheWorlds) {
  const std::string script = write("state.txt", "run 1\nstate\n");
  auto state = [&](std::vector<std::string> args) {
    args.insert(args.begin(), {"--script", script});
    const auto r = run(kMatch, args);
    EXPECT_EQ(r.status, 0) << r.err;
    return r.out.substr(0, r.out.find("final: "));
  };
  const std::string worlds = state({});
  ASSERT_TRUE(contains(worlds, "robot blue1 blue ")) << worlds;
  EXPECT_EQ(state({"--seed", "2001"}), worlds);
  EXPECT_NE(state({"--seed", "0"}), worlds);
  EXPECT_EQ(state({"--seed", "0"}), state({"--seed", "0"}));
}

TEST_P(ConsoleProgram, ExitStatusesFollowOneRule) {
  // 1: the world, the script, or a console on a world that has no match.
  const auto no_world = run(dir_ + "/none.world", {"--fast", "--no-serve"});
  EXPECT_EQ(no_world.status, 1) << no_world.err;
  EXPECT_TRUE(contains(no_world.err, "cannot open world file")) << no_world.err;
  const auto no_script = run(kMatch, {"--script", dir_ + "/none.txt"});
  EXPECT_EQ(no_script.status, 1);
  EXPECT_TRUE(contains(no_script.err, dir_ + "/none.txt: cannot open")) << no_script.err;
  for (const char* option : {"--interactive", "--quiet"}) {
    const auto stage = run(kStageWorld, {"--fast", "--no-serve", option});
    EXPECT_EQ(stage.status, 1) << option;
    EXPECT_TRUE(contains(
        stage.err, std::string(option) + " is for RoboCup worlds; " + kStageWorld + " is a Stage world"))
        << stage.err;
  }
  // 2: the command line, before anything is loaded.
  const auto unknown = run(kMatch, {"--no-such-option"});
  EXPECT_EQ(unknown.status, 2);
  const auto seconds = run(kMatch, {"--seconds", "3"});
  EXPECT_EQ(seconds.status, 2);
  EXPECT_TRUE(contains(seconds.err, "--seconds is gone: --quit-time S")) << seconds.err;
  const auto both = run(kMatch, {"--script", "x.txt", "--quit-time", "3"});
  EXPECT_EQ(both.status, 2);
  EXPECT_TRUE(contains(both.err, "--quit-time with --script: the commands say how far")) << both.err;
}

INSTANTIATE_TEST_SUITE_P(SimAndAlias, ConsoleProgram, ::testing::ValuesIn(kPrograms),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           return param.index == 0 ? std::string("troupe_sim")
                                                   : std::string("troupe_robocup");
                         });

// The alias is troupe-sim --fast --no-serve: the same match, flat out, with
// nothing served, and nothing that would need serving accepted.
TEST(RobocupAlias, IsTroupeSimFlatOutAndUnserved) {
  const std::string alias = kBin + "troupe-robocup";
  const auto r = testing::run_to_end({alias, kMatch, "--quit-time", "2", "--quiet"}, 120000);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out.rfind("final: blue 0 yellow 0 after 2.00 s simulated in ", 0), 0u) << r.out;
  EXPECT_FALSE(contains(r.out, "listening on")) << r.out;
  const auto same = testing::run_to_end(
      {kBin + "troupe-sim", kMatch, "--fast", "--no-serve", "--quit-time", "2", "--quiet"}, 120000);
  EXPECT_EQ(same.out.substr(0, same.out.find(" in ")), r.out.substr(0, r.out.find(" in ")));
  // The CLI runs troupe-robocup from its own folder: the same run.
  const auto cli =
      testing::run_to_end({kBin + "troupe", "robocup", kMatch, "--quit-time", "2", "--quiet"}, 120000);
  EXPECT_EQ(cli.status, 0) << cli.err;
  EXPECT_EQ(cli.out.substr(0, cli.out.find(" in ")), r.out.substr(0, r.out.find(" in ")));
  const auto paused = testing::run_to_end({alias, kMatch, "--paused"}, 60000);
  EXPECT_EQ(paused.status, 2);
  EXPECT_TRUE(contains(
      paused.err, "troupe-robocup: --paused with troupe-robocup, which is --no-serve: nothing is served"))
      << paused.err;
  const auto help = testing::run_to_end({alias, "--help"}, 60000);
  EXPECT_EQ(help.status, 0);
  EXPECT_EQ(help.out.rfind("usage: troupe-robocup WORLD", 0), 0u) << help.out;
  EXPECT_TRUE(contains(help.out, "troupe-sim --fast --no-serve under another name")) << help.out;
}

}  // namespace
}  // namespace troupe::robocup
