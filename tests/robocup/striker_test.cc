// The example striker (examples/robocup/striker) drives a served robot from
// features over TCP, in lockstep with the paused simulator: it reaches the
// ball, kicks it, and the ball goes towards the goal it attacks.
#include "examples/robocup/striker/striker.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "tests/robocup/serve_fixture.h"
#include "tests/support/child_process.h"

namespace troupe::robocup::test {
namespace {

// The example's robots on the 2001 field: the client's striker (yellow,
// attacks the blue goal at -x) and a blue keeper standing in its goal.
const char* kWorld = R"(
include "robots/keeper.inc"
include "robots/pioneer.inc"
interval_sim 10
restitution 0.5
friction 0.3
seed 11
robocup_field ( length 9 width 5 )
ball ( radius 0.11 mass 0.43 deceleration 0.4 pose [-1.5 0.8 0 0] )
referee ( goal_pause 1 duration 0 )
keeper ( name "blue0" team "blue" pose [-4.15 0 0 0] player ( plugin "goalkeeper" policy "none" ) )
pioneer ( name "yellow3" team "yellow" pose [1 -0.5 0 180] )
)";

class StrikerTest : public ServedWorld {
 protected:
  void SetUp() override { serve(kWorld); }
};

TEST_F(StrikerTest, ReachesTheBallAndKicksItTowardsTheGoal) {
  client::Client c("127.0.0.1", port());
  ASSERT_TRUE(c.connect()) << c.error();
  client::SimulationProxy sim(c);
  examples::Striker striker(c, examples::StrikerOptions{});
  std::string error;
  ASSERT_TRUE(striker.start(error)) << error;

  client::Pose2 robot, ball;
  ASSERT_TRUE(sim.get_pose("yellow3", robot));
  ASSERT_TRUE(sim.get_pose("ball", ball));
  const double start_distance = std::hypot(robot.x - ball.x, robot.y - ball.y);
  double closest = start_distance, ball_min_x = ball.x;
  bool scored = false;
  // Up to 20 simulated seconds, one decision per cycle.
  for (int cycle = 0; cycle < 2000 && !scored; ++cycle) {
    ASSERT_TRUE(sim.step(1));
    ASSERT_TRUE(c.sync());  // this cycle's data has arrived
    striker.tick();
    ASSERT_TRUE(c.sync());  // the command is in effect
    ASSERT_TRUE(sim.get_pose("yellow3", robot));
    ASSERT_TRUE(sim.get_pose("ball", ball));
    closest = std::min(closest, std::hypot(robot.x - ball.x, robot.y - ball.y));
    ball_min_x = std::min(ball_min_x, ball.x);
    scored = sim.game().score_yellow > 0;
  }
  // Touching: the ball against the kicker plate is 0.36 m from the centre.
  EXPECT_LT(closest, 0.42f) << "the striker never reached the ball (start " << start_distance << " m)";
  EXPECT_GE(striker.kicks(), 1u);
  EXPECT_TRUE(scored || ball_min_x < -3.0f) << "the ball got only as far as x = " << ball_min_x;
  EXPECT_EQ(sim.game().score_blue, 0u);
}

// The example program as a newcomer runs it, against the example match
// served in this process: in lockstep it plays 20 s deterministically.
class StrikerProgram : public ServedWorld {
 protected:
  void SetUp() override {
    WorldSpec spec;
    std::string error;
    ASSERT_TRUE(load_world_file(TROUPE_SOURCE_DIR "/examples/robocup/match.world", spec, error)) << error;
    sim_ = Simulation::create(std::move(spec), PluginLoader({kPluginDir}), error);
    ASSERT_TRUE(sim_) << error;
    loop_ = std::make_unique<ServeLoop>(*sim_);
    ServeOptions o;
    o.port = 0;
    o.paused = true;  // from the kick-off: the striker steps it
    ASSERT_TRUE(loop_->start(o, error)) << error;
    thread_ = std::thread([this] { loop_->run(); });
  }
};

TEST_F(StrikerProgram, PlaysTheExampleMatch) {
  const std::string target = "127.0.0.1:" + std::to_string(port());
  const auto run =
      troupe::testing::run_to_end({STRIKER_PROGRAM, target, "--lockstep", "--seconds", "20"}, 120000);
  const std::string& text = run.out;
  ASSERT_EQ(run.status, 0) << text << run.err;
  const size_t at = text.find("done: ");
  ASSERT_NE(at, std::string::npos) << text;
  double seconds = 0, closest = 0;
  unsigned kicks = 0;
  ASSERT_EQ(std::sscanf(text.c_str() + at, "done: %lf s simulated, kicks %u, closest to the ball %lf m",
                        &seconds, &kicks, &closest),
            3)
      << text;
  EXPECT_NEAR(seconds, 20.0, 0.011);
  // It reached the ball (0.36 m: the ball against the kicker plate) and
  // kicked it, with seven other players in the game.
  EXPECT_LT(closest, 0.42) << text;
  EXPECT_GE(kicks, 1u) << text;
}

}  // namespace
}  // namespace troupe::robocup::test
