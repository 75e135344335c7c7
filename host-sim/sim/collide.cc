// Collisions: a robot's move is taken only when its outline, swept in steps
// no longer than a grid cell, meets no obstacle cell, and its new outline
// meets no other robot where that robot is or is about to be. Every robot is
// judged against the same before/after poses, so the result does not depend
// on the order robots are stored in; a refused robot stays put and stalls.
#include <algorithm>
#include <cmath>

#include "host-sim/sim/engine.h"

namespace troupe::sim {

void Engine::outline(RobotId i, const Pose& at, std::vector<Vec2>& out_verts,
                     std::vector<PolyRef>& out_polys) const {
  const Body& b = bodies[i];
  out_verts.clear();
  out_polys.clear();
  const double c = std::cos(at.a), s = std::sin(at.a);
  for (uint32_t k = 0; k < b.poly_count; ++k) {
    const PolyRef& p = polys[b.poly_first + k];
    out_polys.push_back({uint32_t(out_verts.size()), p.count});
    for (uint32_t v = 0; v < p.count; ++v) {
      Vec2 q = verts[p.first + v];
      out_verts.push_back({at.x + c * q.x - s * q.y, at.y + s * q.x + c * q.y});
    }
  }
}

void Engine::broadphase() {
  // Each robot enters the hash with the circle that holds it before and
  // after this step's move, so the same hash serves collisions and sensors.
  for (size_t i = 0; i < bodies.size(); ++i) {
    const Body& b = bodies[i];
    const double half = 0.5 * std::hypot(b.proposed.x - b.pose.x, b.proposed.y - b.pose.y);
    hash_centres[i] = {0.5 * (b.pose.x + b.proposed.x), 0.5 * (b.pose.y + b.proposed.y)};
    hash_radii[i] = b.radius + half;
    hash_flags[i] = (b.ranger_visible ? kHashRangerVisible : 0u) | (b.obstacle ? kHashObstacle : 0u);
  }
  // Robots another process owns and none of ours can reach stay out.
  if (!residence.empty()) {
    for (size_t i = 0; i < bodies.size(); ++i) {
      if (residence[i] == kAbsent) hash_radii[i] = -1;
    }
  }
  hash.build(hash_centres, hash_radii, hash_flags);
}

bool Engine::hits_static(RobotId i, const Pose& from, const Pose& to) {
  const Body& b = bodies[i];
  const double travel =
      std::hypot(to.x - from.x, to.y - from.y) + std::fabs(wrap_angle(to.a - from.a)) * b.radius;
  // Far from every occupied cell: nothing to test.
  const double need = b.radius + travel;
  if (map.clearance({from.x, from.y}, need) > need) return false;
  // Sub-steps no longer than a cell, so no wall is jumped over (up to a
  // cap that only absurd speeds reach: thousands of cells in one step).
  const int n = int(std::clamp(std::ceil(travel / map.resolution()), 1.0, 4096.0));
  for (int k = 1; k <= n; ++k) {
    const double f = double(k) / n;
    Pose p{from.x + f * (to.x - from.x), from.y + f * (to.y - from.y),
           from.a + f * wrap_angle(to.a - from.a)};
    outline(i, p, scratch_verts, scratch_polys);
    for (const PolyRef& poly : scratch_polys) {
      if (map.overlaps({scratch_verts.data() + poly.first, poly.count}, StaticMap::kObstacleMask))
        return true;
    }
  }
  return false;
}

bool Engine::overlaps_robot(RobotId i, const Pose& pi, RobotId j, const Pose& pj) {
  bool have_own = false;
  return meets_robot(i, pi, have_own, j, pj);
}

bool Engine::meets_robot(RobotId i, const Pose& pi, bool& have_own, RobotId j, const Pose& pj) {
  const double reach = bodies[i].radius + bodies[j].radius;
  if (std::hypot(pi.x - pj.x, pi.y - pj.y) > reach) return false;
  if (!have_own) {
    outline(i, pi, scratch_verts, scratch_polys);
    have_own = true;
  }
  outline(j, pj, scratch_verts2, scratch_polys2);
  for (const PolyRef& a : scratch_polys) {
    for (const PolyRef& c : scratch_polys2) {
      if (polygons_overlap({scratch_verts.data() + a.first, a.count},
                           {scratch_verts2.data() + c.first, c.count})) {
        return true;
      }
    }
  }
  return false;
}

void Engine::collide() {
  const size_t n = bodies.size();
  for (RobotId i = 0; i < n; ++i) {
    const Body& b = bodies[i];
    accept[i] = 1;
    if (!b.moved || !owns(i)) continue;
    bool blocked = hits_static(i, b.pose, b.proposed);
    if (!blocked && b.obstacle) {
      // Its own outline at the proposed pose is computed once, for the
      // first neighbour near enough, and kept for the others (in a packed
      // crowd, a handful).
      bool have_own = false;
      hash.query(hash_centres[i], hash_radii[i], [&](uint32_t j) {
        if (blocked || j == i || !bodies[j].obstacle) return;
        const Body& o = bodies[j];
        blocked = meets_robot(i, b.proposed, have_own, j, o.pose) ||
                  (o.moved && meets_robot(i, b.proposed, have_own, j, o.proposed));
      });
    }
    accept[i] = blocked ? 0 : 1;
  }
  take_accepted_moves();
}

void Engine::take_accepted_moves() {
  for (RobotId i = 0; i < bodies.size(); ++i) {
    if (!owns(i)) continue;  // a ghost ends its move where its owner says
    Body& b = bodies[i];
    if (!b.moved) {
      b.stalled = false;
      continue;
    }
    if (accept[i]) {
      b.pose = b.proposed;
      b.stalled = false;
    } else {
      // Blocked: the robot stops where it was, as a real one would.
      b.blocked_at = b.proposed;
      b.proposed = b.pose;
      b.vel = {};
      b.moved = false;
      b.stalled = true;
    }
  }
}

}  // namespace troupe::sim
