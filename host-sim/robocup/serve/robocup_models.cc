// simulation:0 of a RoboCup world, as the one request handler
// (host-sim/sim_control/sim_requests.h) asks: poses of robots and the ball,
// the models and the field for viewers, player plugins and the game.
#include <algorithm>
#include <cmath>

#include "host-sim/robocup/serve/robocup_server.h"

namespace troupe::robocup {
namespace {

constexpr uint32_t kBlue = 0x1E50FF, kYellow = 0xFFD21E, kBall = 0xFF7A00;
/// The ball has no devices: no robot number.
constexpr uint16_t kNoRobot = 0xFFFF;

// The robot's footprint, a box centred on its origin that holds its shapes.
Vec2 footprint(const RobotSpec& spec) {
  Vec2 half;
  for (const Shape& s : spec.shapes) {
    const Aabb box = bounds(place(s, {}));
    half.x = std::max({half.x, std::fabs(box.lo.x), std::fabs(box.hi.x)});
    half.y = std::max({half.y, std::fabs(box.lo.y), std::fabs(box.hi.y)});
  }
  return 2 * half;
}

}  // namespace

sim::SimTime RobocupServer::now() const {
  return {sim_.time_s(), uint64_t(std::llround(sim_.time_s() / sim_.cycle_s()))};
}

bool RobocupServer::get_pose(const std::string& name, Pose2& pose, bool& has_velocity, Pose2& velocity,
                             std::string& error) {
  has_velocity = true;
  if (name == "ball") {
    const BallInfo ball = sim_.ball();
    pose = {ball.position.x, ball.position.y, 0};
    velocity = {ball.velocity.x, ball.velocity.y, 0};
    return true;
  }
  const int robot = sim_.find_robot(name);
  if (robot < 0) {
    error = "no model named '" + name + "' (robot names and 'ball')";
    return false;
  }
  const RobotInfo info = sim_.robot(robot);
  pose = info.pose;
  velocity = {info.velocity.vx, info.velocity.vy, info.velocity.w};
  return true;
}

bool RobocupServer::set_pose(const std::string& name, const Pose2& pose, const Pose2* velocity,
                             std::string& error) {
  if (name == "ball") {
    sim_.place_ball(pose.position(), velocity ? Vec2{velocity->x, velocity->y} : Vec2{});
    return true;
  }
  const int robot = sim_.find_robot(name);
  if (robot < 0) {
    error = "no model named '" + name + "' (robot names and 'ball')";
    return false;
  }
  sim_.place_robot(robot, pose);
  return true;
}

flatbuffers::Offset<wire::SimModelList> RobocupServer::models(flatbuffers::FlatBufferBuilder& b) {
  std::vector<flatbuffers::Offset<wire::SimModelInfo>> list;
  for (int r = 0; r < sim_.robot_count(); ++r) {
    const RobotEntry& e = sim_.spec().robots[size_t(r)];
    const Vec2 size = footprint(e.spec);
    list.push_back(wire::CreateSimModelInfo(b, b.CreateString(e.name), uint16_t(r), float(size.x), float(size.y),
                                            e.team == Team::Blue ? kBlue : kYellow, wire::SimShape::Box));
  }
  const float ball = float(2 * sim_.spec().ball.radius);
  list.push_back(wire::CreateSimModelInfo(b, b.CreateString("ball"), kNoRobot, ball, ball, kBall, wire::SimShape::Disc));
  const FieldSpec& f = sim_.spec().field;
  auto field = wire::CreateSimField(b, float(f.length), float(f.width), float(f.goal_width), float(f.goal_depth),
                                    float(f.border), float(f.center_circle_radius), float(f.penalty_depth),
                                    float(f.penalty_width), float(f.corner_post_radius), float(f.corner_post_offset));
  return wire::CreateSimModelList(b, b.CreateVector(list), field);
}

bool RobocupServer::start_player(const std::string& robot, const std::string& plugin,
                                 const std::vector<std::pair<std::string, std::string>>& options,
                                 std::string& error) {
  Options o("simulation:0 StartPlayer", "");
  for (const auto& [k, v] : options) o.set(k, v);
  return sim_.start_player(robot, plugin, o, error);
}

bool RobocupServer::stop_player(const std::string& robot, std::string& error) {
  if (sim_.find_robot(robot) < 0) {
    error = "no robot named '" + robot + "'";
    return false;
  }
  sim_.stop_player(robot);
  return true;
}

bool RobocupServer::game(flatbuffers::FlatBufferBuilder& b, flatbuffers::Offset<wire::SimGame>& out) {
  out = build_game(b);
  return true;
}

void RobocupServer::publish_poses(const Device& d) {
  scratch_poses_.clear();
  for (int r = 0; r < sim_.robot_count(); ++r) {
    const Pose2& p = sim_.robot(r).pose;
    scratch_poses_.emplace_back(float(p.x), float(p.y), float(p.a));
  }
  const Vec2 ball = sim_.ball().position;
  scratch_poses_.emplace_back(float(ball.x), float(ball.y), 0.0f);
  auto& b = node_->begin();
  auto poses = b.CreateVectorOfStructs(scratch_poses_);
  auto body = wire::CreateSimPoses(b, uint64_t(std::llround(sim_.time_s() * 1e6)), poses);
  node_->publish(d.id, uint8_t(wire::SimulationDataSub::Poses), wire::Body::SimPoses, body.Union());
}

}  // namespace troupe::robocup
