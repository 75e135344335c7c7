#include "host-sim/robocup/game/world_desc.h"

#include <algorithm>
#include <cmath>

#include "host-sim/sim/ball.h"

namespace troupe::robocup {
namespace {

// The top of the tallest shape with a finite top, m; `fallback` if none.
double top_of(const std::vector<Shape>& shapes, double fallback) {
  double top = 0;
  for (const Shape& s : shapes) {
    if (std::isfinite(s.z_max)) top = std::max(top, s.z_max);
  }
  return top > 0 ? top : fallback;
}

// A robot of the engine whose rigid body is `rigid` (undriven: the game
// layer moves it) and whose outline, for rays and cameras, is `outlined`.
sim::RobotDesc body(const std::string& name, Pose2 at, const std::vector<Shape>& outlined, double height,
                    uint32_t color, double mass, sim::RigidDesc rigid) {
  sim::RobotDesc r;
  r.name = name;
  r.pose = at;
  double reach = 0;
  for (const Shape& s : outlined) {
    r.polygons.push_back(outline(s));
    for (Vec2 p : r.polygons.back()) reach = std::max({reach, std::fabs(p.x), std::fabs(p.y)});
  }
  r.size = {2 * reach, 2 * reach};
  r.look.color = color;
  r.look.height = height;
  r.mass = mass;
  rigid.driven = false;
  r.rigid = std::move(rigid);
  return r;
}

// A robot's Stage sensor models, their cameras stacked on its height (m).
void add_sensors(const sim::RobotDesc& from, double height, sim::RobotDesc& to) {
  to.rangers = from.rangers;
  to.blobfinders = from.blobfinders;
  to.fiducials = from.fiducials;
  to.bumpers = from.bumpers;
  to.grippers = from.grippers;
  to.cameras = from.cameras;
  for (sim::CameraDesc& c : to.cameras) c.z += height;
}

}  // namespace

std::vector<Shape> robot_shapes(const RobotSpec& spec, int kicker_state) {
  std::vector<Shape> shapes = spec.shapes;
  if (spec.has_kicker) {
    for (const Shape& s : spec.kicker.states[size_t(kicker_state)].shapes) shapes.push_back(s);
  }
  return shapes;
}

sim::WorldDesc world_desc(const WorldSpec& spec, const FieldColors& colors) {
  sim::WorldDesc w;
  w.physics = sim::Physics::Rigid;
  w.rigid = spec.physics;
  w.resolution = 0.02;
  w.interval_sim = spec.physics.cycle_s;

  // The field's bodies from the one description of where they stand.
  World field_world(spec.physics);
  std::vector<BodyId> ids;
  build_field(spec.field, field_world, ids);
  for (BodyId id : ids) {
    const uint64_t user = field_world.user_data(id);
    const auto part = FieldPart(user_tag(user));
    const std::span<const Shape> shapes = field_world.shapes(id);
    sim::StaticDesc s;
    s.pose = field_world.pose(id);
    s.rigid_shapes.assign(shapes.begin(), shapes.end());
    s.rigid_user_data = user;
    // The physics stops bodies at it; the grid only shows it.
    s.look.obstacle = false;
    double reach_x = 0, reach_y = 0, top = 0;
    for (const Shape& shape : shapes) {
      s.polygons.push_back(outline(shape));
      for (Vec2 p : s.polygons.back()) {
        reach_x = std::max(reach_x, std::fabs(p.x));
        reach_y = std::max(reach_y, std::fabs(p.y));
      }
      top = std::max(top, shape.z_max);
    }
    s.size = {2 * reach_x, 2 * reach_y};
    s.look.height = top;
    const bool yellow_side = s.pose.x > 0;  // goal 1 and the corner posts at +x
    switch (part) {
      case FieldPart::Barrier:
        s.name = "barrier";
        s.look.color = colors.barrier;
        break;
      case FieldPart::GoalWall:
        s.name = yellow_side ? "yellow_goal" : "blue_goal";
        s.look.color = yellow_side ? colors.yellow_goal : colors.blue_goal;
        break;
      case FieldPart::CornerPost:
        s.name = "corner_post";
        s.look.color = yellow_side ? colors.yellow_goal : colors.blue_goal;
        break;
    }
    w.statics.push_back(std::move(s));
  }

  const FieldGeometry g = field_geometry(spec.field);
  w.floor.color = colors.carpet;
  const double line = spec.field.line_width;
  for (const LineSegment& l : g.lines) w.floor.marks.push_back({l.a, l.b, 0, line, colors.lines});
  if (g.center_circle_radius > 0) {
    w.floor.marks.push_back({{0, 0}, {0, 0}, g.center_circle_radius, line, colors.lines});
  }

  sim::BallDesc ball;
  ball.radius = spec.ball.radius;
  ball.mass = spec.ball.mass;
  ball.deceleration = spec.ball.deceleration;
  ball.pose = {spec.ball.start.x, spec.ball.start.y, 0};
  ball.color = colors.ball;
  ball.user_data = make_user_data(kBallTag, 0);
  w.robots.push_back(sim::ball_robot(ball));
  for (size_t k = 0; k < spec.robots.size(); ++k) {
    const RobotEntry& e = spec.robots[k];
    sim::RigidDesc rigid;
    rigid.shapes = robot_shapes(e.spec, 0);
    rigid.inertia = e.spec.inertia;
    rigid.user_data = make_user_data(kRobotTag, uint32_t(k));
    const double height = top_of(e.spec.shapes, 0.6);
    w.robots.push_back(
        body(e.name, e.start, e.spec.shapes, height, colors.robot, e.spec.mass, std::move(rigid)));
    if (e.stage_sensors) add_sensors(*e.stage_sensors, height, w.robots.back());
  }
  return w;
}

}  // namespace troupe::robocup
