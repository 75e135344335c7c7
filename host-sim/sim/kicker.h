// Stage robots' kickers (a `kicker` model on a position robot, rigid worlds
// only): fired, a kicker's plate sends every ball or puck touching it away
// by RoboCup's kick rule (robocup/physics/kick.h), then recovers for its
// `hold` time. A kick happens when it is asked for, between steps, as a
// command does; the step's physics then carries the ball on.
//
// Kept beside the World rather than inside its step: kicking needs only the
// World's rigid bodies, and what fires it (a client, a controller) sits
// outside the step too.
#pragma once

#include <cstdint>
#include <vector>

#include "host-sim/robocup/physics/shape.h"
#include "host-sim/sim/world.h"

namespace troupe::sim {

class Kickers {
 public:
  /// Every robot's kickers (WorldDesc robots' `kickers`), numbered
  /// world-wide in robot order. None in a kinematic world (the loader
  /// refuses kickers there).
  explicit Kickers(World& world);

  size_t count() const { return kickers_.size(); }
  RobotId owner(uint32_t index) const { return kickers_.at(index).robot; }
  /// The robot's kickers by world-wide index: [first, first + count).
  IndexRange of(RobotId robot) const;
  /// At rest: a kick fires at once. Not while it recovers from the last
  /// kick (KickerDesc::hold, simulated s).
  bool ready(uint32_t index) const;
  /// Fires kicker `index` when ready: every ball or puck touching its plate
  /// gains accel * contact m/s along the kicker's heading. Returns how many
  /// it kicked (0 too when not ready; the kicker then stays as it was).
  int kick(uint32_t index);

 private:
  struct Kicker {
    RobotId robot = 0;
    KickerDesc desc;
    /// The plate, robot frame (a rigid shape, as RoboCup's kickers have).
    robocup::Shape plate;
    /// Simulated time of the last kick, s.
    double kicked_at = -1e300;
  };

  World& world_;
  std::vector<Kicker> kickers_;
  std::vector<IndexRange> of_robot_;
  /// The robots a kick may move: pucks (balls among them).
  std::vector<RobotId> pucks_;
};

}  // namespace troupe::sim
