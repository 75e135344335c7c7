// The swarm behaviour as a pure function of what one robot senses, shared
// by the in-process controller (swarm.cc) and the over-the-wire example
// (swarm_clients/), so both drive the robots the same way.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

namespace troupe::examples {

struct SwarmParams {
  bool aggregate = true;  // false: disperse
  double speed = 0.3;     // m/s
  double spacing = 0.8;   // m: near enough (aggregate), far enough (disperse)
  double avoid = 0.35;    // m: an obstacle this close ahead makes it turn
};

struct SwarmInputs {
  /// Ranger readings (m) and each one's bearing on the robot (rad).
  std::vector<float> ranges;
  std::vector<double> bearings;
  /// Neighbours seen by the fiducial finder: position in the robot frame, m.
  struct Neighbour {
    double x, y;
  };
  std::vector<Neighbour> neighbours;
  bool has_fiducial = false;
};

/// What persists between decisions (the wandering's current bias).
struct SwarmState {
  int wiggle = 0;
  double bias = 0;
};

struct SwarmCommand {
  double v = 0;  // m/s forward
  double w = 0;  // rad/s
};

/// One decision. `uniform(k)` gives seeded random numbers in [0, 1).
inline SwarmCommand swarm_decide(const SwarmParams& p, const SwarmInputs& in, SwarmState& st,
                                 const std::function<double(int)>& uniform) {
  constexpr double kPi = 3.14159265358979323846;
  double nearest = 1e9, nearest_bearing = 0, ahead = 1e9;
  for (size_t i = 0; i < in.ranges.size() && i < in.bearings.size(); ++i) {
    if (in.ranges[i] < nearest) {
      nearest = in.ranges[i];
      nearest_bearing = in.bearings[i];
    }
    if (std::fabs(in.bearings[i]) < kPi / 4) ahead = std::min(ahead, double(in.ranges[i]));
  }
  double sx = 0, sy = 0, closest = 1e9, closest_bearing = 0;
  size_t seen = 0;
  if (in.has_fiducial) {
    for (const SwarmInputs::Neighbour& n : in.neighbours) {
      sx += n.x;
      sy += n.y;
      ++seen;
      const double r = std::hypot(n.x, n.y);
      if (r < closest) {
        closest = r;
        closest_bearing = std::atan2(n.y, n.x);
      }
    }
  } else if (nearest < 1e9) {
    closest = nearest;
    closest_bearing = nearest_bearing;
    seen = 1;
  }
  // Turn towards `bearing`, driving once roughly facing it.
  auto steer = [&](double bearing) {
    return SwarmCommand{std::fabs(bearing) < kPi / 3 ? p.speed : 0.0, std::clamp(1.5 * bearing, -1.5, 1.5)};
  };
  if (p.aggregate) {
    if (seen == 0) {
      // Alone: wander until someone comes into view.
      if (ahead < p.avoid) return {0, 1.0};
      if (--st.wiggle <= 0) {
        st.wiggle = 10 + int(uniform(0) * 30);
        st.bias = (uniform(1) - 0.5) * 1.5;
      }
      return {p.speed, st.bias};
    }
    if (closest < p.spacing) return {0, 0};
    if (ahead < p.avoid) return {0, nearest_bearing > 0 ? -1.0 : 1.0};
    return steer(std::atan2(sy / double(seen), sx / double(seen)));
  }
  if (seen == 0 || closest >= p.spacing) return {0, 0};
  return steer(std::remainder(closest_bearing + kPi, 2 * kPi));
}

}  // namespace troupe::examples
