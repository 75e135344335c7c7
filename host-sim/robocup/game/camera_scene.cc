#include "host-sim/robocup/game/camera_scene.h"

#include <algorithm>
#include <cmath>

namespace troupe::robocup {
namespace {

// Sides of the polygon a round shape becomes: the grid's cells are coarser
// than the difference on field-sized posts and balls.
constexpr int kRoundSides = 24;

// A shape's outline in its body's frame, m.
std::vector<sim::Vec2> outline(const Shape& s) {
  std::vector<sim::Vec2> out;
  if (s.kind == ShapeKind::Polygon) {
    out.assign(s.vertices, s.vertices + s.vertex_count);
    return out;
  }
  const double rx = s.kind == ShapeKind::Circle ? s.radius : s.rx;
  const double ry = s.kind == ShapeKind::Circle ? s.radius : s.ry;
  for (int i = 0; i < kRoundSides; ++i) {
    const double t = 2 * kPi * i / kRoundSides;
    out.push_back(s.center + rotate({rx * std::cos(t), ry * std::sin(t)}, s.angle));
  }
  return out;
}

// The top of the tallest shape with a finite top, m; `fallback` if none.
double top_of(const std::vector<Shape>& shapes, double fallback) {
  double top = 0;
  for (const Shape& s : shapes) {
    if (std::isfinite(s.z_max)) top = std::max(top, s.z_max);
  }
  return top > 0 ? top : fallback;
}

sim::RobotDesc body(const std::string& name, Pose2 at, const std::vector<Shape>& shapes, double height,
                    uint32_t color) {
  sim::RobotDesc r;
  r.name = name;
  r.pose = at;
  double reach = 0;
  for (const Shape& s : shapes) {
    r.polygons.push_back(outline(s));
    for (Vec2 p : r.polygons.back()) reach = std::max({reach, std::fabs(p.x), std::fabs(p.y)});
  }
  r.size = {2 * reach, 2 * reach};
  r.look.color = color;
  r.look.height = height;
  return r;
}

}  // namespace

sim::WorldDesc camera_scene(const WorldSpec& spec, const FieldColors& colors) {
  sim::WorldDesc w;
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

  const std::vector<Shape> ball = {make_circle({0, 0}, spec.ball.radius)};
  w.robots.push_back(
      body("ball", {spec.ball.start.x, spec.ball.start.y, 0}, ball, 2 * spec.ball.radius, colors.ball));
  for (const RobotEntry& e : spec.robots) {
    w.robots.push_back(body(e.name, e.start, e.spec.shapes, top_of(e.spec.shapes, 0.6), colors.robot));
  }
  return w;
}

}  // namespace troupe::robocup
