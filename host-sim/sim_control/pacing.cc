#include "host-sim/sim_control/pacing.h"

#include <algorithm>

#include "runtime/clock.h"

namespace troupe::sim {

void RateMeter::update(SimControl& control, double sim_s, uint64_t now_us, bool final) {
  if (wall_us_ == 0 || sim_s < sim_s_) {  // first call, or the clock went back (a reset)
    wall_us_ = now_us;
    sim_s_ = sim_s;
  } else if (now_us - wall_us_ >= 1000000 || (final && now_us > wall_us_)) {
    control.real_time_factor = (sim_s - sim_s_) / (double(now_us - wall_us_) * 1e-6);
    wall_us_ = now_us;
    sim_s_ = sim_s;
  }
}

void run_paced(SimControl& control, const std::atomic<bool>& stop, const LoopParts& parts, RateMeter& rate,
               const std::function<void()>& after_step) {
  // Real-time pacing: simulated time `anchor_sim` was reached at wall time
  // `anchor_wall` (re-anchored on resume, on a change of speed, and when
  // the clock went back: a reset).
  uint64_t anchor_wall = 0;
  double anchor_sim = 0, anchor_speed = -1, last_time = 0;
  bool anchored = false;
  while (!stop) {
    if (parts.done && parts.done()) break;
    if (control.paused) {
      anchored = false;
      parts.serve(kMaxWaitUs);
      continue;
    }
    const double t = parts.time_s();
    if (t < last_time) anchored = false;
    last_time = t;
    if (control.speed > 0) {
      const uint64_t now = monotonic_us();
      if (!anchored || anchor_speed != control.speed) {
        anchor_wall = now;
        anchor_sim = t;
        anchor_speed = control.speed;
        anchored = true;
      }
      const double due = double(anchor_wall) + (t - anchor_sim) / control.speed * 1e6;
      if (double(now) < due) {
        parts.serve(std::min<int64_t>(kMaxWaitUs, int64_t(due - double(now)) + 1));
        continue;
      }
    } else {
      anchored = false;
    }
    parts.serve(0);
    if (stop || control.paused) continue;
    parts.step();
    rate.update(control, parts.time_s(), monotonic_us());
    if (after_step) after_step();
  }
}

}  // namespace troupe::sim
