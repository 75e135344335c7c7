// Rays against placed shapes: what laser, ultrasonic and camera occlusion
// tests are made of.
#pragma once

#include "host-sim/robocup/physics/shape.h"

namespace troupe::robocup {

/// Where a ray first enters a shape: distance along the ray (m) and the
/// surface normal there (world, unit).
struct RayShapeHit {
  double distance = 0;
  Vec2 normal;
};

/// The first entry of the ray `origin + t * dir` (dir unit, 0 <= t <=
/// max_range m) into `s`. A ray starting inside a shape does not hit it
/// (a sensor inside its own housing sees out).
bool raycast(const PlacedShape& s, Vec2 origin, Vec2 dir, double max_range, RayShapeHit& hit);

}  // namespace troupe::robocup
