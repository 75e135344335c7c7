// The rigid-body motion model (a world's `physics "rigid"`): the integrate
// and collide phases over host-sim/robocup/physics. Robots are rigid bodies
// whose velocity is set every step to the one the control phase commands
// (wheels hold them to it), so they push each other and pucks by impulses;
// pucks keep what they are given and slow down by floor friction. Walls
// stay in the static map: a body whose move would cross an obstacle cell
// (the kinematic model's swept test) is put back and stopped, so is one
// that would move into a body put back, and a robot so stopped stalls.
#include <cmath>
#include <string>

#include "host-sim/robocup/physics/world.h"
#include "host-sim/sim/engine.h"

namespace troupe::sim {

struct RigidBodies {
  explicit RigidBodies(const robocup::WorldDef& def) : world(def) {}
  robocup::World world;
  /// One per engine body; kNoBody for a body that is no obstacle (it moves
  /// through everything, as in the kinematic model) or is being carried.
  std::vector<robocup::BodyId> ids;
  /// The engine body's shapes, body frame, kept to recreate it.
  std::vector<std::vector<robocup::Shape>> shapes;
};

namespace {

// Impacts between robots and pucks hardly bounce: robots are heavy wheeled
// bases and pucks slide, they are not balls.
constexpr double kRestitution = 0.1;
constexpr double kFriction = 0.3;
// A pushed puck slides to rest by floor friction, m/s^2 and rad/s^2.
constexpr double kPuckDeceleration = 2.0;
constexpr double kPuckSpinDeceleration = 4.0;

}  // namespace

void RigidBodiesDelete::operator()(RigidBodies* r) const {
  delete r;
}

void Engine::build_rigid() {
  robocup::WorldDef def;
  def.cycle_s = desc.interval_sim;
  def.restitution = kRestitution;
  def.friction = kFriction;
  rigid.reset(new RigidBodies(def));
  rigid->ids.assign(bodies.size(), robocup::kNoBody);
  for (RobotId i = 0; i < bodies.size(); ++i) {
    const Body& b = bodies[i];
    std::vector<robocup::Shape> shapes;
    for (uint32_t k = 0; k < b.poly_count; ++k) {
      const PolyRef& p = polys[b.poly_first + k];
      const std::span<const Vec2> corners(verts.data() + p.first, p.count);
      robocup::Shape s;
      std::string why;
      if (!robocup::make_polygon(corners, s, why)) {
        // Concave or many-cornered: the circle about its corners' centre.
        Vec2 c;
        for (Vec2 v : corners) c = c + v;
        c = (1.0 / double(p.count)) * c;
        double r = 0;
        for (Vec2 v : corners) r = std::max(r, length(v - c));
        s = robocup::make_circle(c, std::max(r, 1e-3));
      }
      shapes.push_back(s);
    }
    rigid->shapes.push_back(std::move(shapes));
    sync_rigid(i);
  }
}

void Engine::sync_rigid(RobotId i) {
  RigidBodies& r = *rigid;
  const Body& b = bodies[i];
  robocup::World& w = r.world;
  if (!b.obstacle) {
    if (w.valid(r.ids[i])) w.destroy_body(r.ids[i]);
    r.ids[i] = robocup::kNoBody;
    return;
  }
  if (!w.valid(r.ids[i])) {
    robocup::BodyDef def;
    def.pose = b.pose;
    def.mass = desc.robots[i].mass;
    def.shapes = r.shapes[i];
    def.user_data = i;
    if (desc.robots[i].puck) {
      def.linear_deceleration = kPuckDeceleration;
      def.angular_deceleration = kPuckSpinDeceleration;
    }
    std::string why;
    r.ids[i] = w.create_body(def, why);
    // The shapes were validated when made; a body that still cannot be
    // made moves kinematically (through other bodies), as if no obstacle.
    if (!w.valid(r.ids[i])) return;
  }
  w.set_pose(r.ids[i], b.pose);
  const double c = std::cos(b.pose.a), s = std::sin(b.pose.a);
  w.set_origin_velocity(r.ids[i], {c * b.vel.x - s * b.vel.y, s * b.vel.x + c * b.vel.y, b.vel.a});
}

void Engine::rigid_integrate() {
  // Bodies without a rigid body (no obstacle) move as in the kinematic
  // model; the others are overwritten below.
  integrate();
  RigidBodies& r = *rigid;
  robocup::World& w = r.world;
  for (RobotId i = 0; i < bodies.size(); ++i) {
    if (desc.robots[i].puck || !w.valid(r.ids[i])) continue;
    const Body& b = bodies[i];
    const double c = std::cos(b.pose.a), s = std::sin(b.pose.a);
    w.set_origin_velocity(r.ids[i], {c * b.vel.x - s * b.vel.y, s * b.vel.x + c * b.vel.y, b.vel.a});
  }
  w.step();
  for (RobotId i = 0; i < bodies.size(); ++i) {
    if (!w.valid(r.ids[i])) continue;
    Body& b = bodies[i];
    const Pose p = w.pose(r.ids[i]);
    b.proposed = {p.x, p.y, wrap_angle(p.a)};
    b.moved = b.proposed.x != b.pose.x || b.proposed.y != b.pose.y || b.proposed.a != b.pose.a;
    if (desc.robots[i].puck) {
      // A puck's velocity is what the impacts gave it, in its own frame.
      const robocup::Twist v = w.velocity(r.ids[i]);
      const double c = std::cos(b.pose.a), s = std::sin(b.pose.a);
      b.vel = {c * v.vx + s * v.vy, -s * v.vx + c * v.vy, v.w};
    }
  }
}

void Engine::rigid_collide() {
  RigidBodies& r = *rigid;
  robocup::World& w = r.world;
  const size_t n = bodies.size();
  // Moves into a wall are refused; then, until nothing changes, so are
  // moves into a body whose move was refused (a puck pinned to a wall stops
  // the robot pushing it, rather than letting the robot into it).
  for (RobotId i = 0; i < n; ++i)
    accept[i] = !bodies[i].moved || !hits_static(i, bodies[i].pose, bodies[i].proposed);
  for (bool changed = true; changed;) {
    changed = false;
    for (RobotId i = 0; i < n; ++i) {
      const Body& b = bodies[i];
      if (!b.moved || !accept[i] || !b.obstacle) continue;
      hash.query(hash_centres[i], hash_radii[i], [&](uint32_t j) {
        if (!accept[i] || j == i || accept[j] || !bodies[j].obstacle) return;
        if (overlaps_robot(i, b.proposed, j, bodies[j].pose)) {
          accept[i] = 0;
          changed = true;
        }
      });
    }
  }
  take_accepted_moves();
  // The refused stay where they were in the physics too, stopped.
  for (RobotId i = 0; i < n; ++i) {
    if (accept[i] || !w.valid(r.ids[i])) continue;
    w.set_pose(r.ids[i], bodies[i].pose);
    w.set_velocity(r.ids[i], {});
  }
}

}  // namespace troupe::sim
