#include "host-sim/robocup/game/referee.h"

#include <algorithm>

namespace troupe::robocup {

bool read_referee(const Statement& st, RefereeSpec& r, std::string& error) {
  Options o = st.reader();
  r.goal_pause_s = o.number("goal_pause", r.goal_pause_s, 0, 60);
  r.out_inset = o.number("out_inset", r.out_inset, 0, 10);
  r.duration_s = o.number("duration", r.duration_s, 0, 1e7);
  r.enabled = o.flag("enabled", r.enabled);
  if (!o.finish(error)) {
    error = st.where() + ": referee: " + error;
    return false;
  }
  return true;
}

const char* event_name(RefereeEventKind kind) {
  switch (kind) {
    case RefereeEventKind::Goal:
      return "goal";
    case RefereeEventKind::BallOut:
      return "ball-out";
    case RefereeEventKind::Reset:
      return "reset";
    case RefereeEventKind::TimeUp:
      return "time-up";
  }
  return "?";
}

RefereeDecision Referee::judge(double t, Vec2 ball, double r) {
  last_.clear();
  RefereeDecision d;
  if (!spec_.enabled || phase_ == GamePhase::Stopped) return d;
  if (spec_.duration_s > 0 && t >= spec_.duration_s) {
    phase_ = GamePhase::Stopped;
    emit({RefereeEventKind::TimeUp, t, Team::Blue, ball, ball});
    return d;
  }
  if (phase_ == GamePhase::GoalPause) {
    if (t >= pause_until_s_) {
      phase_ = GamePhase::Play;
      d.reset = true;
      emit({RefereeEventKind::Reset, t, Team::Blue, ball, {0, 0}});
    }
    return d;
  }
  const double hx = field_.length / 2, hy = field_.width / 2;
  // A goal: the whole ball behind the goal line, between the posts (the
  // goal's walls keep a ball that got there inside the mouth's width).
  if (std::fabs(ball.x) >= hx + r && std::fabs(ball.x) <= hx + field_.goal_depth &&
      std::fabs(ball.y) <= field_.goal_width / 2) {
    const Team scorer = ball.x < 0 ? Team::Yellow : Team::Blue;
    (scorer == Team::Blue ? score_.blue : score_.yellow) += 1;
    phase_ = GamePhase::GoalPause;
    pause_until_s_ = t + spec_.goal_pause_s;
    emit({RefereeEventKind::Goal, t, scorer, ball, ball});
    if (spec_.goal_pause_s == 0) {
      phase_ = GamePhase::Play;
      d.reset = true;
      emit({RefereeEventKind::Reset, t, Team::Blue, ball, {0, 0}});
    }
    return d;
  }
  // Out: the whole ball over a touch line, or over a goal line beside the
  // goal. It goes back inside, near where it left.
  if (std::fabs(ball.x) >= hx + r || std::fabs(ball.y) >= hy + r) {
    const double ix = std::max(0.0, hx - spec_.out_inset), iy = std::max(0.0, hy - spec_.out_inset);
    d.place_ball = true;
    d.ball_to = {std::clamp(ball.x, -ix, ix), std::clamp(ball.y, -iy, iy)};
    emit({RefereeEventKind::BallOut, t, Team::Blue, ball, d.ball_to});
  }
  return d;
}

}  // namespace troupe::robocup
