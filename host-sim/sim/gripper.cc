// Stage's gripper: closing catches the puck whose centre lies in the
// gripper's footprint (between the paddles) and carries it rigidly with the
// robot; opening drops it where it is. A carried puck is no obstacle (its
// carrier would otherwise be blocked by it) and, in rigid mode, no body:
// it rides along until dropped.
#include <cmath>

#include "host-sim/sim/engine.h"

namespace troupe::sim {
namespace {

bool held_by_any(const std::vector<GripperState>& grippers, RobotId puck) {
  for (const GripperState& g : grippers) {
    if (g.holding && g.held == puck) return true;
  }
  return false;
}

}  // namespace

void Engine::update_grippers() {
  for (GripperState& g : grippers) {
    const Body& robot = bodies[g.robot];
    if (g.want_closed && !g.closed) {
      g.closed = true;
      const Pose frame = compose(robot.pose, g.pose);
      const double reach = std::hypot(g.half_size.x, g.half_size.y);
      double best = 1e300;
      hash.query({frame.x, frame.y}, reach, [&](uint32_t j) {
        if (!desc.robots[j].puck || held_by_any(grippers, j)) return;
        const Vec2 local = relative(frame, bodies[j].pose).position();
        if (std::fabs(local.x) > g.half_size.x || std::fabs(local.y) > g.half_size.y) return;
        // The nearest to the footprint's centre; the lower index on a tie,
        // so the result does not depend on the hash's order.
        const double d = length(local);
        if (d < best || (d == best && j < g.held)) {
          best = d;
          g.held = j;
          g.holding = true;
        }
      });
      if (g.holding) {
        g.offset = relative(robot.pose, bodies[g.held].pose);
        Body& p = bodies[g.held];
        p.vel = {};
        p.obstacle = false;
        if (rigid) sync_rigid(g.held);
      }
    } else if (!g.want_closed && g.closed) {
      g.closed = false;
      if (g.holding) {
        g.holding = false;
        bodies[g.held].obstacle = desc.robots[g.held].look.obstacle;
        if (rigid) sync_rigid(g.held);
      }
    }
    if (g.holding) {
      Body& p = bodies[g.held];
      p.pose = compose(robot.pose, g.offset);
      p.pose.a = wrap_angle(p.pose.a);
      p.proposed = p.pose;
    }
  }
}

}  // namespace troupe::sim
