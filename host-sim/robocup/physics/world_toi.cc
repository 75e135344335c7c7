// Time of impact: conservative advancement. Two convex shapes a distance d
// apart, closing along their normal at most at u (translation projected on
// the normal plus each body's spin times its reach), cannot touch before
// d / u; stepping by that bound until they are within the contact band
// finds the first contact without skipping thin walls.
#include <algorithm>

#include "host-sim/robocup/physics/world.h"

namespace troupe::robocup {

Pose2 World::pose_after(const Body& b, double t) {
  if (b.inv_mass == 0) return b.pose;
  const Vec2 com = com_world(b) + b.v * t;
  const double a = b.pose.a + b.w * t;
  const Vec2 origin = com - rotate(b.local_com, a);
  return {origin.x, origin.y, a};
}

void World::advance(double dt) {
  for (Body& b : bodies_) {
    if (!b.alive || b.inv_mass == 0) continue;
    const Pose2 p = pose_after(b, dt);
    b.pose = {p.x, p.y, wrap_angle(p.a)};
    place_body(b);
  }
}

double World::time_of_impact(const Body& a, const Body& b, double horizon) const {
  constexpr int kMaxPairs = 64;
  constexpr int kMaxIterations = 32;
  const double target = def_.contact_slop * 0.5;
  const double tolerance = def_.contact_slop * 0.25;
  // Shape pairs that can touch and do not touch yet (touching ones belong
  // to the contact solver).
  uint16_t pairs[kMaxPairs][2];
  int count = 0;
  for (size_t i = 0; i < a.shapes.size(); ++i) {
    for (size_t j = 0; j < b.shapes.size() && count < kMaxPairs; ++j) {
      if (!heights_overlap(a.shapes[i], b.shapes[j])) continue;
      if (separation(a.placed[i], b.placed[j]).distance < def_.contact_slop) continue;
      pairs[count][0] = uint16_t(i);
      pairs[count][1] = uint16_t(j);
      ++count;
    }
  }
  if (count == 0) return horizon;
  const double spin = std::fabs(a.w) * a.reach + std::fabs(b.w) * b.reach;
  double t = 0;
  for (int it = 0; it < kMaxIterations; ++it) {
    const Pose2 pa = pose_after(a, t), pb = pose_after(b, t);
    double step = kUnboundedZ;
    for (int k = 0; k < count; ++k) {
      const Separation s = separation(place(a.shapes[pairs[k][0]], pa), place(b.shapes[pairs[k][1]], pb));
      if (s.distance < target + tolerance) return t;
      const double closing = std::max(0.0, dot(a.v - b.v, s.normal)) + spin;
      if (closing > 1e-12) step = std::min(step, (s.distance - target) / closing);
    }
    if (step == kUnboundedZ) return horizon;
    t += step;
    if (t >= horizon) return horizon;
  }
  return t;
}

double World::earliest_impact(double horizon) const {
  double best = horizon;
  auto swept = [](const Body& b, double dt) {
    const double spin = std::fabs(b.w) * dt * b.reach;
    const Vec2 d = b.v * dt;
    return Aabb{
        {std::min(b.box.lo.x, b.box.lo.x + d.x) - spin, std::min(b.box.lo.y, b.box.lo.y + d.y) - spin},
        {std::max(b.box.hi.x, b.box.hi.x + d.x) + spin, std::max(b.box.hi.y, b.box.hi.y + d.y) + spin}};
  };
  for (uint32_t i = 0; i < bodies_.size(); ++i) {
    for (uint32_t j = i + 1; j < bodies_.size(); ++j) {
      const Body& a = bodies_[i];
      const Body& b = bodies_[j];
      if (!a.alive || !b.alive || (a.inv_mass == 0 && b.inv_mass == 0)) continue;
      const Aabb sa = swept(a, best), sb = swept(b, best);
      const Vec2 slop{def_.contact_slop, def_.contact_slop};
      if (!Aabb{sa.lo - slop, sa.hi + slop}.overlaps(sb)) continue;
      best = std::min(best, time_of_impact(a, b, best));
    }
  }
  return best;
}

}  // namespace troupe::robocup
