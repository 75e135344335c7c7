// Distance and penetration between two placed convex shapes: GJK on the
// shapes' cores (circles are a point plus their radius), a support-function
// separating-axis search when the cores overlap, and contact points for
// the impulse solver (two of them when flat faces lie against each other).
#pragma once

#include "host-sim/robocup/physics/shape.h"

namespace troupe::robocup {

struct Separation {
  /// Gap between the shapes, m; negative: penetration depth.
  double distance = 0;
  /// Unit vector from A towards B: moving B along it separates them.
  Vec2 normal{1, 0};
  /// Contact points, world, m: midway between the surfaces. Two when two
  /// flat faces lie against each other (the ends of their overlap).
  int point_count = 1;
  Vec2 points[2];
};

/// Distance between `a` and `b`. Heights are not considered here.
Separation separation(const PlacedShape& a, const PlacedShape& b);

}  // namespace troupe::robocup
