// The rigid-body motion model (a world's `physics "rigid"`): the integrate
// and collide phases over host-sim/robocup/physics. Robots are rigid bodies
// whose velocity is set every step to the one the control phase commands
// (wheels hold them to it), so they push each other and pucks by impulses;
// pucks keep what they are given and slow down by floor friction. Walls
// stay in the static map: a body whose move would cross an obstacle cell
// (the kinematic model's swept test) is put back and stopped, so is one
// that would move into a body put back, and a robot so stopped stalls.
// Statics with rigid shapes are static bodies instead (a RoboCup field's
// barrier, goals and posts, which a ball bounces off); robots with a
// RigidDesc bring their exact shapes and mass properties, and undriven ones
// keep the velocity their owner (World::rigid()) and the impacts give them.
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
  /// Per engine body: the engine sets its velocity from its command.
  std::vector<uint8_t> driven;
  /// One per static model; kNoBody for one without rigid shapes.
  std::vector<robocup::BodyId> static_ids;
};

namespace {

// A pushed puck slides to rest by floor friction, m/s^2 and rad/s^2.
constexpr double kPuckDeceleration = 2.0;
constexpr double kPuckSpinDeceleration = 4.0;

}  // namespace

void RigidBodiesDelete::operator()(RigidBodies* r) const {
  delete r;
}

void Engine::build_rigid() {
  robocup::WorldDef def = desc.rigid;
  def.cycle_s = desc.interval_sim;
  rigid.reset(new RigidBodies(def));
  // Statics before robots: bodies are made in the description's order, so
  // a world described in the order of an older one steps as it did.
  for (const StaticDesc& s : desc.statics) {
    robocup::BodyId id = robocup::kNoBody;
    if (!s.rigid_shapes.empty()) {
      robocup::BodyDef d;
      d.pose = compose(s.pose, s.origin);
      d.shapes = s.rigid_shapes;
      d.user_data = s.rigid_user_data;
      std::string why;
      // A static whose shapes are invalid stays a grid model only.
      id = rigid->world.create_body(d, why);
    }
    rigid->static_ids.push_back(id);
  }
  rigid->ids.assign(bodies.size(), robocup::kNoBody);
  for (RobotId i = 0; i < bodies.size(); ++i) {
    const Body& b = bodies[i];
    const RobotDesc& rd = desc.robots[i];
    rigid->driven.push_back(rd.rigid ? rd.rigid->driven : !rd.puck);
    if (rd.rigid && !rd.rigid->shapes.empty()) {
      rigid->shapes.push_back(rd.rigid->shapes);
      sync_rigid(i);
      continue;
    }
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
  const RobotDesc& rd = desc.robots[i];
  if (!w.valid(r.ids[i])) {
    robocup::BodyDef def;
    def.pose = b.pose;
    def.mass = rd.mass;
    def.shapes = r.shapes[i];
    def.user_data = i;
    if (rd.rigid) {
      def.inertia = rd.rigid->inertia;
      def.linear_deceleration = rd.rigid->linear_deceleration;
      def.angular_deceleration = rd.rigid->angular_deceleration;
      def.user_data = rd.rigid->user_data;
    } else if (rd.puck) {
      def.linear_deceleration = kPuckDeceleration;
      def.angular_deceleration = kPuckSpinDeceleration;
    }
    std::string why;
    r.ids[i] = w.create_body(def, why);
    // The shapes were validated when made; a body that still cannot be
    // made moves kinematically (through other bodies), as if no obstacle.
    if (!w.valid(r.ids[i])) return;
    // A described body starts as its definition says: at rest, where it
    // stands, touched by no further call (its owner's calls come next).
    if (rd.rigid && b.vel.x == 0 && b.vel.y == 0 && b.vel.a == 0) return;
  }
  w.set_pose(r.ids[i], b.pose);
  const double c = std::cos(b.pose.a), s = std::sin(b.pose.a);
  w.set_origin_velocity(r.ids[i], {c * b.vel.x - s * b.vel.y, s * b.vel.x + c * b.vel.y, b.vel.a});
}

void Engine::rigid_integrate() {
  // Bodies without a rigid body (no obstacle) move as in the kinematic
  // model; the physics moves the others.
  RigidBodies& r = *rigid;
  robocup::World& w = r.world;
  for (RobotId i = 0; i < bodies.size(); ++i) {
    if (!w.valid(r.ids[i])) integrate_body(bodies[i], desc.interval_sim);
  }
  for (RobotId i = 0; i < bodies.size(); ++i) {
    if (!r.driven[i] || !w.valid(r.ids[i])) continue;
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
    if (!r.driven[i]) read_rigid_velocity(i);
  }
}

void Engine::read_rigid_velocity(RobotId i) {
  // What the impacts and the owner gave it (its centre of mass's), in its
  // own frame.
  const robocup::Twist v = rigid->world.velocity(rigid->ids[i]);
  Body& b = bodies[i];
  const double c = std::cos(b.pose.a), s = std::sin(b.pose.a);
  b.vel = {c * v.vx + s * v.vy, -s * v.vx + c * v.vy, v.w};
}

void Engine::rigid_moved() {
  RigidBodies& r = *rigid;
  for (RobotId i = 0; i < bodies.size(); ++i) {
    if (!r.world.valid(r.ids[i])) continue;
    Body& b = bodies[i];
    const Pose p = r.world.pose(r.ids[i]);
    b.pose = b.proposed = {p.x, p.y, wrap_angle(p.a)};
    b.moved = false;
    if (!r.driven[i]) read_rigid_velocity(i);
  }
  publish_states();
  broadphase();
}

robocup::World* Engine::rigid_world() {
  return rigid ? &rigid->world : nullptr;
}

robocup::BodyId Engine::rigid_body(RobotId i) const {
  return rigid && i < rigid->ids.size() ? rigid->ids[i] : robocup::kNoBody;
}

robocup::BodyId Engine::rigid_static_body(size_t k) const {
  return rigid && k < rigid->static_ids.size() ? rigid->static_ids[k] : robocup::kNoBody;
}

void Engine::rigid_collide() {
  RigidBodies& r = *rigid;
  robocup::World& w = r.world;
  const size_t n = bodies.size();
  // Moves into a wall are refused; then, until nothing changes, so are
  // moves into a body whose move was refused (a puck pinned to a wall stops
  // the robot pushing it, rather than letting the robot into it).
  const bool walls = map.has_obstacles();
  for (RobotId i = 0; i < n; ++i)
    accept[i] = !bodies[i].moved || !walls || !hits_static(i, bodies[i].pose, bodies[i].proposed);
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
