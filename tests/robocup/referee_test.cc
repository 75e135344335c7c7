// The referee: goals, ball out, resets and time, judged on the real
// field with the real physics (a ball rolled by hand).
#include <gtest/gtest.h>

#include "sim_fixture.h"

namespace troupe::robocup {
namespace {

TEST(Referee, JudgesGoalsOnlyWhenTheWholeBallIsIn) {
  FieldSpec f;
  Referee ref(f, {});
  const double r = 0.11;
  EXPECT_FALSE(ref.judge(0, {4.5 + r - 0.01, 0}, r).reset);
  EXPECT_TRUE(ref.last_events().empty()) << "on the line is not in";
  ref.judge(0.01, {4.5 + r + 0.01, 0.5}, r);
  ASSERT_EQ(ref.last_events().size(), 1u);
  EXPECT_EQ(ref.last_events()[0].kind, RefereeEventKind::Goal);
  EXPECT_EQ(ref.last_events()[0].team, Team::Blue) << "a ball in the yellow goal is blue's goal";
  EXPECT_EQ(ref.score(), (Score{1, 0}));
  EXPECT_EQ(ref.phase(), GamePhase::GoalPause);
  // No second goal while the ball sits in the net; the reset after the pause.
  EXPECT_FALSE(ref.judge(0.5, {4.8, 0.5}, r).reset);
  EXPECT_TRUE(ref.judge(1.01, {4.8, 0.5}, r).reset);
  EXPECT_EQ(ref.score(), (Score{1, 0}));
  EXPECT_EQ(ref.phase(), GamePhase::Play);
}

TEST(Referee, PutsAnOutBallBackInsideNearWhereItLeft) {
  FieldSpec f;
  Referee ref(f, {});
  RefereeDecision d = ref.judge(0, {1.0, 2.5 + 0.12}, 0.11);
  ASSERT_TRUE(d.place_ball);
  EXPECT_EQ(d.ball_to.x, 1.0);
  EXPECT_EQ(d.ball_to.y, 2.0);
  // Over the goal line beside the goal: back inside at the corner's inset.
  d = ref.judge(0.1, {-4.5 - 0.2, -1.6}, 0.11);
  ASSERT_TRUE(d.place_ball);
  EXPECT_EQ(d.ball_to.x, -4.0);
  EXPECT_EQ(d.ball_to.y, -1.6);
  EXPECT_EQ(ref.last_events()[0].kind, RefereeEventKind::BallOut);
  EXPECT_EQ(ref.score(), Score{}) << "out is no goal";
}

TEST(Referee, StopsWhenTimeIsUp) {
  RefereeSpec spec;
  spec.duration_s = 10;
  Referee ref(FieldSpec{}, spec);
  ref.judge(9.99, {0, 0}, 0.11);
  EXPECT_EQ(ref.phase(), GamePhase::Play);
  ref.judge(10.0, {0, 0}, 0.11);
  EXPECT_EQ(ref.phase(), GamePhase::Stopped);
  EXPECT_EQ(ref.last_events()[0].kind, RefereeEventKind::TimeUp);
  ref.judge(10.01, {4.8, 0}, 0.11);
  EXPECT_EQ(ref.score(), Score{}) << "nothing counts after the end";
}

TEST(Game, ARolledBallScoresAndTheFieldIsReset) {
  std::string error;
  auto sim = test::make_sim(
      "referee ( goal_pause 0.5 )\nball ( pose [0 0 0 0] )\n" + test::robot("b1", "blue", -2, 1, 0, test::pioneer_block()),
      error);
  ASSERT_TRUE(sim) << error;
  sim->place_ball({3.0, 0.3}, {4, 0});
  sim->place_robot(0, {-1, -1, 1});
  std::vector<RefereeEventKind> seen;
  for (int i = 0; i < 200; ++i) {
    sim->step();
    for (const RefereeEvent& e : sim->events()) seen.push_back(e.kind);
  }
  ASSERT_EQ(seen, (std::vector<RefereeEventKind>{RefereeEventKind::Goal, RefereeEventKind::Reset}));
  EXPECT_EQ(sim->score(), (Score{1, 0}));
  EXPECT_NEAR(length(sim->ball().position), 0, 1e-9) << "the ball is back on the centre spot";
  EXPECT_NEAR(sim->robot(0).pose.x, -2, 1e-6) << "robots are back at kick-off";
  EXPECT_NEAR(sim->robot(0).pose.y, 1, 1e-6);
}

TEST(Game, TheGoalsWallsStopAShotBallAndItCountsOnce) {
  std::string error;
  auto sim = test::make_sim("referee ( goal_pause 2 )\nball ( )\n", error);
  ASSERT_TRUE(sim) << error;
  sim->place_ball({3.5, 0.4}, {8, 0});
  int goals = 0;
  for (int i = 0; i < 150; ++i) {
    sim->step();
    for (const RefereeEvent& e : sim->events()) goals += e.kind == RefereeEventKind::Goal;
    const Vec2 b = sim->ball().position;
    ASSERT_LE(b.x, 4.5 + 0.6 - 0.11 + 1e-3) << "through the back wall at step " << i;
    ASSERT_LE(std::fabs(b.y), 2.5) << "through a side wall at step " << i;
  }
  EXPECT_EQ(goals, 1) << "one goal, though the ball bounced off the back wall back out";
}

TEST(Game, ABallOverTheTouchLineComesBackClearOfRobots) {
  std::string error;
  auto sim = test::make_sim(test::robot("b1", "blue", 1, 2, 0, test::pioneer_block()), error);
  ASSERT_TRUE(sim) << error;
  sim->place_ball({1.0, 2.3}, {0, 2});
  bool out = false;
  for (int i = 0; i < 50 && !out; ++i) {
    sim->step();
    for (const RefereeEvent& e : sim->events()) out = out || e.kind == RefereeEventKind::BallOut;
  }
  ASSERT_TRUE(out);
  EXPECT_LT(sim->ball().position.y, 2.5);
  EXPECT_GT(sim->physics().distance(sim->ball_body(), sim->robot_body(0)).distance, 0)
      << "the referee did not drop the ball onto the robot standing at the spot";
}

}  // namespace
}  // namespace troupe::robocup
