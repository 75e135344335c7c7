// The one loop every simulator runs (troupe-sim's Stage worlds and RoboCup
// worlds alike): steps in real time, a multiple of it, or as fast as
// possible, as SimControl says; answers the network between steps, at
// least every kMaxWaitUs; sleeps while paused. The simulator brings its
// parts: its clock, its serving, its whole step.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>

#include "host-sim/sim_control/sim_control.h"

namespace troupe::sim {

struct LoopParts {
  /// Simulated time now, s.
  std::function<double()> time_s;
  /// Polls the network (and whatever else the loop serves), waiting at most
  /// `wait_us` (0: not at all).
  std::function<void(int64_t wait_us)> serve;
  /// One step of the whole simulation (world, controllers, publishing).
  std::function<void()> step;
  /// True when the run is over (a quit time, the game's end); checked
  /// before every step. May be empty.
  std::function<bool()> done;
};

/// The network is answered at least this often, us.
inline constexpr int64_t kMaxWaitUs = 50000;

/// Measures simulated seconds per wall second over a second or more into
/// SimControl::real_time_factor.
class RateMeter {
 public:
  /// `final`: measure now, however short the interval.
  void update(SimControl& control, double sim_s, uint64_t now_us, bool final = false);

 private:
  uint64_t wall_us_ = 0;
  double sim_s_ = 0;
};

/// Runs until `stop` is set or parts.done(); updates the rate in `control`.
/// `after_step` (may be empty) runs after each step, e.g. a progress line.
void run_paced(SimControl& control, const std::atomic<bool>& stop, const LoopParts& parts,
               RateMeter& rate, const std::function<void()>& after_step = {});

}  // namespace troupe::sim
