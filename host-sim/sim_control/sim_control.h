// simulation:0's clock controls, which every simulator answers alike:
// Pause, Resume, GetClock, Step and SetSpeed, each acknowledged with the
// clock (SimClock) as it stands once the request took effect. The loop that
// runs the simulator owns a SimControl and reads it; the server edits it.
#pragma once

#include <cstdint>
#include <functional>

#include "runtime/node.h"

namespace troupe::sim {

/// What the simulation device changes in the running loop.
struct SimControl {
  bool paused = false;
  /// Multiple of real time; 0: as fast as possible.
  double speed = 1;
  /// Measured simulated seconds per wall second (for SimClock; 0 before it
  /// is known).
  double real_time_factor = 0;
  /// Runs n steps now (the loop's whole step: world, controllers,
  /// publishing), for the Step request, which is acked once they ran.
  std::function<void(uint32_t)> step;
  /// When set, a Step request is handed to the loop instead of `step`: the
  /// loop runs the n steps in slices, serving every client between them,
  /// and answers `token` itself (ack_clock) after the last one.
  std::function<void(uint32_t n, RequestToken token)> start_steps;
  /// Every model back to its start, for the Reset request (troupe-sim; a
  /// simulator that resets by itself leaves it empty).
  std::function<void()> reset;
};

/// A simulator's clock, read when an answer is written.
struct SimTime {
  /// simulated time since the start, s
  double time_s = 0;
  /// steps run since the start
  uint64_t steps = 0;
};

/// Acks `token` with a SimClock of `now` and `control`.
void ack_clock(Node& node, const SimControl& control, RequestToken token, SimTime now);

/// Answers `req` when it is Pause, Resume, GetClock, Step or SetSpeed (a bad
/// Step count or speed gets a Nack saying why); `clock` is read after the
/// request took effect. A Step handed to `control.start_steps` is answered
/// later by the loop. Other requests get a Nack: the caller answers those.
void answer_clock_request(Node& node, SimControl& control, const wire::Message& req, RequestToken token,
                          const std::function<SimTime()>& clock);

}  // namespace troupe::sim
