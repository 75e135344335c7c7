// The referee: counts goals, puts the ball back when it leaves the field,
// and resets the field after a goal. It only judges; the simulation carries
// out its decisions (it owns the bodies).
//
//   referee goal_pause=1 out_inset=0.5 duration=0 enabled=1
#pragma once

#include <string>
#include <vector>

#include "host-sim/robocup/api/world_view.h"
#include "host-sim/robocup/game/statement.h"
#include "host-sim/robocup/game/field.h"

namespace troupe::robocup {

struct RefereeSpec {
  /// Pause after a goal before the field is reset, s.
  double goal_pause_s = 1.0;
  /// How far inside the lines a ball that went out is put back, m.
  double out_inset = 0.5;
  /// Game length, s; 0: no limit.
  double duration_s = 0;
  bool enabled = true;
};

bool read_referee(const Statement& statement, RefereeSpec& out, std::string& error);

enum class RefereeEventKind : uint8_t {
  /// `team` scored.
  Goal = 0,
  /// The ball left the field at `where` and was put back at `to`.
  BallOut = 1,
  /// Robots and ball went back to their kick-off places.
  Reset = 2,
  /// The game's time ran out.
  TimeUp = 3,
};

struct RefereeEvent {
  RefereeEventKind kind;
  /// Simulated time, s.
  double time_s = 0;
  Team team = Team::Blue;
  /// World, m.
  Vec2 where, to;
};

const char* event_name(RefereeEventKind kind);

/// What the simulation must do after the referee looked at a cycle.
struct RefereeDecision {
  /// Put the ball, stopped, at `ball_to`.
  bool place_ball = false;
  Vec2 ball_to;
  /// Every robot and the ball back to their start.
  bool reset = false;
};

class Referee {
 public:
  Referee(const FieldSpec& field, const RefereeSpec& spec) : field_(field), spec_(spec) {}

  /// Judges the ball (world, m; radius m) at `time_s` after a physics step.
  RefereeDecision judge(double time_s, Vec2 ball, double ball_radius);

  const Score& score() const { return score_; }
  GamePhase phase() const { return phase_; }
  /// Events of the last judge(), and of the whole game.
  const std::vector<RefereeEvent>& last_events() const { return last_; }
  const std::vector<RefereeEvent>& history() const { return history_; }
  /// Back to play, e.g. after the simulation reset the field by hand.
  void restart() {
    phase_ = GamePhase::Play;
    pause_until_s_ = 0;
  }
  /// Halts the game (phase Stopped) until restart().
  void halt() { phase_ = GamePhase::Stopped; }

 private:
  void emit(RefereeEvent e) {
    last_.push_back(e);
    history_.push_back(e);
  }

  FieldSpec field_;
  RefereeSpec spec_;
  Score score_;
  GamePhase phase_ = GamePhase::Play;
  double pause_until_s_ = 0;
  std::vector<RefereeEvent> last_, history_;
};

}  // namespace troupe::robocup
