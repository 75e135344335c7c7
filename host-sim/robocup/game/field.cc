#include "host-sim/robocup/game/field.h"

namespace troupe::robocup {

bool read_field(const Statement& st, FieldSpec& f, std::string& error) {
  Options o = st.reader();
  f.length = o.number("length", f.length, 1, 100);
  f.width = o.number("width", f.width, 1, 100);
  f.border = o.number("border", f.border, 0, 20);
  f.barrier_thickness = o.number("barrier_thickness", f.barrier_thickness, 0.01, 2);
  f.barrier_height = o.number("barrier_height", f.barrier_height, 0.01, 10);
  f.goal_width = o.number("goal_width", f.goal_width, 0.1, 50);
  f.goal_depth = o.number("goal_depth", f.goal_depth, 0.05, 10);
  f.goal_height = o.number("goal_height", f.goal_height, 0.05, 10);
  f.goal_wall = o.number("goal_wall", f.goal_wall, 0.005, 1);
  f.corner_post_radius = o.number("corner_post_radius", f.corner_post_radius, 0, 2);
  f.corner_post_offset = o.number("corner_post_offset", f.corner_post_offset, 0, 20);
  f.corner_post_height = o.number("corner_post_height", f.corner_post_height, 0.01, 10);
  f.center_circle_radius = o.number("center_circle_radius", f.center_circle_radius, 0, 50);
  f.penalty_depth = o.number("penalty_depth", f.penalty_depth, 0, 50);
  f.penalty_width = o.number("penalty_width", f.penalty_width, 0, 100);
  f.line_width = o.number("line_width", f.line_width, 0.001, 1);
  if (o.ok()) {
    if (f.goal_width + 2 * f.goal_wall >= f.width) {
      o.fail("goal_width", "the goal (with its walls) must be narrower than the field");
    } else if (f.goal_depth + f.goal_wall > f.border) {
      o.fail("border", "must leave room for the goals behind the goal lines (goal_depth + goal_wall)");
    } else if (f.corner_post_radius > 0 && f.corner_post_offset + f.corner_post_radius > f.border) {
      o.fail("corner_post_offset", "corner posts must stand inside the barrier");
    } else if (f.penalty_depth > f.length / 2 || f.penalty_width > f.width) {
      o.fail("penalty_depth", "the penalty area must fit in its half");
    }
  }
  if (!o.finish(error)) {
    error = st.where() + ": field: " + error;
    return false;
  }
  return true;
}

FieldGeometry field_geometry(const FieldSpec& f) {
  FieldGeometry g;
  g.length = f.length;
  g.width = f.width;
  g.goal_width = f.goal_width;
  g.goal_depth = f.goal_depth;
  g.center_circle_radius = f.center_circle_radius;
  g.border = f.border;
  const double hx = f.length / 2, hy = f.width / 2, gy = f.goal_width / 2;
  g.landmarks = {
      {ObjectKind::Goal, 0, {-hx, 0}},      {ObjectKind::Goal, 1, {hx, 0}},
      {ObjectKind::GoalPost, 0, {-hx, gy}}, {ObjectKind::GoalPost, 1, {-hx, -gy}},
      {ObjectKind::GoalPost, 2, {hx, -gy}}, {ObjectKind::GoalPost, 3, {hx, gy}},
  };
  if (f.corner_post_radius > 0) {
    const double cx = hx + f.corner_post_offset, cy = hy + f.corner_post_offset;
    g.landmarks.push_back({ObjectKind::CornerPost, 0, {cx, cy}, f.corner_post_radius});
    g.landmarks.push_back({ObjectKind::CornerPost, 1, {-cx, cy}, f.corner_post_radius});
    g.landmarks.push_back({ObjectKind::CornerPost, 2, {-cx, -cy}, f.corner_post_radius});
    g.landmarks.push_back({ObjectKind::CornerPost, 3, {cx, -cy}, f.corner_post_radius});
  }
  g.lines = {{{-hx, hy}, {hx, hy}},
             {{-hx, -hy}, {hx, -hy}},
             {{-hx, -hy}, {-hx, hy}},
             {{hx, -hy}, {hx, hy}},
             {{0, -hy}, {0, hy}}};
  if (f.penalty_depth > 0 && f.penalty_width > 0) {
    const double px = hx - f.penalty_depth, py = f.penalty_width / 2;
    for (double s : {-1.0, 1.0}) {
      g.lines.push_back({{s * hx, py}, {s * px, py}});
      g.lines.push_back({{s * px, py}, {s * px, -py}});
      g.lines.push_back({{s * px, -py}, {s * hx, -py}});
    }
  }
  return g;
}

void build_field(const FieldSpec& f, World& world, std::vector<BodyId>& bodies) {
  std::string error;
  auto add = [&](Pose2 at, Shape shape, FieldPart part, uint32_t id) {
    BodyDef d;
    d.pose = at;
    d.shapes = {shape};
    d.user_data = make_user_data(uint64_t(part), id);
    bodies.push_back(world.create_body(d, error));
  };
  const double hx = f.length / 2, hy = f.width / 2, t = f.barrier_thickness;
  const double ox = hx + f.border + t / 2, oy = hy + f.border + t / 2;
  const double span_x = 2 * (hx + f.border + t), span_y = 2 * (hy + f.border + t);
  add({0, oy, 0}, with_height(make_rect({0, 0}, span_x, t), 0, f.barrier_height), FieldPart::Barrier, 0);
  add({0, -oy, 0}, with_height(make_rect({0, 0}, span_x, t), 0, f.barrier_height), FieldPart::Barrier, 1);
  add({ox, 0, 0}, with_height(make_rect({0, 0}, t, span_y), 0, f.barrier_height), FieldPart::Barrier, 2);
  add({-ox, 0, 0}, with_height(make_rect({0, 0}, t, span_y), 0, f.barrier_height), FieldPart::Barrier, 3);
  // Each goal: two side walls from the goal line back, and a back wall.
  const double w = f.goal_wall, gy = f.goal_width / 2, d = f.goal_depth;
  for (int goal = 0; goal < 2; ++goal) {
    const double s = goal == 0 ? -1 : 1;
    const uint32_t id = uint32_t(goal);
    const double side_x = s * (hx + d / 2);
    add({side_x, gy + w / 2, 0}, with_height(make_rect({0, 0}, d, w), 0, f.goal_height), FieldPart::GoalWall,
        id);
    add({side_x, -gy - w / 2, 0}, with_height(make_rect({0, 0}, d, w), 0, f.goal_height), FieldPart::GoalWall,
        id);
    add({s * (hx + d + w / 2), 0, 0},
        with_height(make_rect({0, 0}, w, f.goal_width + 2 * w), 0, f.goal_height), FieldPart::GoalWall, id);
  }
  if (f.corner_post_radius > 0) {
    const double cx = hx + f.corner_post_offset, cy = hy + f.corner_post_offset;
    const Vec2 at[4] = {{cx, cy}, {-cx, cy}, {-cx, -cy}, {cx, -cy}};
    for (uint32_t i = 0; i < 4; ++i) {
      add({at[i].x, at[i].y, 0},
          with_height(make_circle({0, 0}, f.corner_post_radius), 0, f.corner_post_height),
          FieldPart::CornerPost, i);
    }
  }
}

}  // namespace troupe::robocup
