// The RoboCup mid-size (F2000) field: its dimensions, the static bodies
// they make (barrier, goals, corner posts) and the landmarks and lines
// sensors see. The defaults are the field of the RoboCup Middle-Size League
// of 2001 as README.md states them; every number is a key of the `field`
// statement, so another year's rules are a text edit.
//
//   field length=9 width=5 border=1 goal_width=2 goal_depth=0.6 ...
#pragma once

#include <string>
#include <vector>

#include "host-sim/robocup/api/world_view.h"
#include "host-sim/robocup/game/statement.h"
#include "host-sim/robocup/physics/world.h"

namespace troupe::robocup {

/// Field dimensions, m. The origin is the centre spot, x towards the yellow
/// goal, y to the left of it.
struct FieldSpec {
  /// Between the goal lines and between the touch lines.
  double length = 9.0, width = 5.0;
  /// Floor beyond the lines up to the barrier that keeps robots and ball in.
  double border = 1.0;
  double barrier_thickness = 0.1, barrier_height = 0.5;
  /// Goal mouth (between the posts), depth behind the goal line, crossbar
  /// height, and the thickness of its walls.
  double goal_width = 2.0, goal_depth = 0.6, goal_height = 1.0, goal_wall = 0.05;
  /// Corner posts: radius and how far outside the corner of the lines
  /// (along both axes) their centres stand, and their height.
  double corner_post_radius = 0.1, corner_post_offset = 0.4, corner_post_height = 1.0;
  double center_circle_radius = 1.0;
  /// Penalty area: depth from the goal line and width.
  double penalty_depth = 1.0, penalty_width = 3.0;
  /// Width of the white lines painted on the carpet (cameras see them).
  double line_width = 0.1;
};

/// Reads a `field` statement over the defaults; false with "file:line:
/// option 'x': why" when a value is bad or the pieces do not fit.
bool read_field(const Statement& statement, FieldSpec& out, std::string& error);

/// Landmarks (goals, goal posts, corner posts) and lines.
FieldGeometry field_geometry(const FieldSpec& spec);

/// What a static body of the field is, kept in its user data.
enum class FieldPart : uint8_t { Barrier = 1, GoalWall = 2, CornerPost = 3 };

/// Adds the field's static bodies to `world`. Their user data is
/// field_user_data(part, id).
void build_field(const FieldSpec& spec, World& world, std::vector<BodyId>& bodies);

/// Body user data of the whole simulation: the high byte says what a body
/// is (1..3: FieldPart, 8: robot, 9: ball), the low 32 bits an id.
inline constexpr uint64_t kRobotTag = 8, kBallTag = 9;
inline uint64_t make_user_data(uint64_t tag, uint32_t id) {
  return (tag << 56) | id;
}
inline uint64_t user_tag(uint64_t user_data) {
  return user_data >> 56;
}
inline uint32_t user_id(uint64_t user_data) {
  return uint32_t(user_data & 0xFFFFFFFFu);
}

}  // namespace troupe::robocup
