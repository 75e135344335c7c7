// The simulation as plugins see it (WorldView, WorldControl).
#include "host-sim/robocup/game/simulation.h"

namespace troupe::robocup {

BallInfo Simulation::ball() const {
  const Twist v = world_.velocity(ball_);
  return {world_.pose(ball_).position(), v.linear(), spec_.ball.radius};
}

RobotInfo Simulation::robot(int index) const {
  if (index < 0 || index >= robot_count()) return {};
  const Robot& r = robots_[size_t(index)];
  const Pose2 pose = world_.pose(r.body);
  const Vec2 v = world_.velocity_at(r.body, pose.position());
  return {r.name, r.team, index, pose, {v.x, v.y, world_.velocity(r.body).w}, r.radius};
}

int Simulation::find_robot(std::string_view name) const {
  for (size_t i = 0; i < robots_.size(); ++i) {
    if (robots_[i].name == name) return int(i);
  }
  return -1;
}

bool Simulation::raycast(Vec2 origin, double angle, double max_range, double z, int ignore_robot,
                         RayResult& out) const {
  const BodyId ignore = robot_body(ignore_robot);
  RayHit hit;
  if (!world_.raycast(origin, direction(angle), max_range, z, ignore, hit)) return false;
  const uint64_t user = world_.user_data(hit.body);
  out.distance = hit.distance;
  out.id = -1;
  switch (user_tag(user)) {
    case kBallTag:
      out.kind = ObjectKind::Ball;
      break;
    case kRobotTag:
      out.kind = ObjectKind::Robot;
      out.id = int(user_id(user));
      break;
    case uint64_t(FieldPart::CornerPost):
      out.kind = ObjectKind::CornerPost;
      out.id = int(user_id(user));
      break;
    default:
      out.kind = ObjectKind::Structure;
      break;
  }
  return true;
}

bool Simulation::line_of_sight(Vec2 from, Vec2 to, double z, int ignore_robot, int target_robot,
                               double clearance) const {
  const double d = length(to - from);
  if (d < 1e-9) return true;
  const BodyId ignore = robot_body(ignore_robot), target = robot_body(target_robot);
  const BodyId ball = ball_;
  RayHit hit;
  return !world_.raycast(
      from, (to - from) / d, std::max(0.0, d - clearance), z,
      [&](BodyId id, uint64_t) { return !(id == ignore) && !(id == target) && !(id == ball); }, hit);
}

void Simulation::place_ball(Vec2 position, Vec2 velocity) {
  world_.set_pose(ball_, {position.x, position.y, 0});
  world_.set_velocity(ball_, {velocity.x, velocity.y, 0});
  engine_->rigid_moved();
}

void Simulation::place_robot(int index, Pose2 pose) {
  if (index < 0 || index >= robot_count()) return;
  world_.set_pose(robots_[size_t(index)].body, pose);
  world_.set_velocity(robots_[size_t(index)].body, {});
  engine_->rigid_moved();
}

}  // namespace troupe::robocup
