#include "host-sim/robocup/physics/kick.h"

#include <algorithm>

namespace troupe::robocup {

bool kick_ball(World& w, BodyId kicker, std::span<const Shape> plates, double reach, double direction_rad,
               double speed, BodyId ball) {
  const Pose2 pose = w.pose(kicker);
  const Shape& round = w.shapes(ball)[0];
  const PlacedShape placed = place(round, w.pose(ball));
  double gap = kUnboundedZ;
  for (const Shape& plate : plates) {
    if (heights_overlap(plate, round)) gap = std::min(gap, separation(place(plate, pose), placed).distance);
  }
  if (gap > reach) return false;
  const Vec2 dv = direction(pose.a + direction_rad) * speed;
  const Twist bv = w.velocity(ball);
  w.set_velocity(ball, {bv.vx + dv.x, bv.vy + dv.y, bv.w});
  w.apply_impulse(kicker, dv * -w.mass(ball), placed.center);
  return true;
}

}  // namespace troupe::robocup
