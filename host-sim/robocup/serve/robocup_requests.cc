// Requests to the served RoboCup devices: sensor geometry and the
// simulation device (clock, poses, players, game).
#include <cmath>
#include <numbers>

#include "host-sim/robocup/serve/robocup_server.h"

namespace troupe::robocup {

using wire::ErrorCode;

void RobocupServer::on_request(DeviceId id, const wire::Message& req, RequestToken token) {
  Device* d = find(id);
  if (d == nullptr) return node_->nack(token, ErrorCode::NoSuchDevice, "not a RoboCup device");
  const uint8_t sub = req.header()->subtype();
  switch (d->kind) {
    case Kind::Simulation:
      return simulation_request(req, token);
    case Kind::Fiducial:
    case Kind::Ranger:
      return sensor_request(*d, req, token);
    case Kind::Position:
      if (sub == uint8_t(wire::Position2dReqSub::MotorPower)) {
        const wire::Switch* sw = req.body_as_Switch();
        if (sw == nullptr)
          return node_->nack(token, ErrorCode::BadArgument, "motor power needs a Switch body");
        d->motors_on = sw->on();
        if (!d->motors_on) sim_.command(d->robot, {});
        return node_->ack(token);
      }
      if (sub == uint8_t(wire::Position2dReqSub::Geometry)) {
        // The robot's reach as a square: the shapes' exact outline has no
        // place in the geometry reply.
        const double r = sim_.robot(d->robot).radius;
        auto& b = node_->begin();
        wire::Pose3d pose(0, 0, 0, 0, 0, 0);
        wire::Vec3 size(float(2 * r), float(2 * r), 0);
        auto body = wire::CreatePosition2dGeometry(b, &pose, &size);
        return node_->ack(token, wire::Body::Position2dGeometry, body.Union());
      }
      if (sub == uint8_t(wire::Position2dReqSub::SetOdometry) ||
          sub == uint8_t(wire::Position2dReqSub::ResetOdometry)) {
        return node_->nack(token, ErrorCode::Unsupported,
                           "RoboCup odometry is a sensor plugin's; it cannot be set over the wire");
      }
      break;
    case Kind::Kicker:
      break;
  }
  Driver::on_request(id, req, token);
}

void RobocupServer::sensor_request(Device& d, const wire::Message& req, RequestToken token) {
  const PluginSpec* spec = sensor_spec(d);
  if (spec == nullptr) return node_->nack(token, ErrorCode::Unknown, "the sensor is gone");
  Options options = spec->options;  // the getters mark keys used: work on a copy
  const double range = options.number("range", 0);
  const double min_range = options.number("min_range", 0);
  wire::Pose3d pose(float(spec->mount.x), float(spec->mount.y), float(spec->mount_z), 0, 0,
                    float(spec->mount.a));
  wire::Vec3 size(0, 0, 0);
  const uint8_t sub = req.header()->subtype();
  if (d.kind == Kind::Fiducial && sub == uint8_t(wire::FiducialReqSub::Geometry)) {
    const double fov = spec->plugin == "omnivision" ? 2 * std::numbers::pi : options.number("fov", 0);
    auto& b = node_->begin();
    auto body = wire::CreateFiducialGeometry(b, &pose, &size, float(min_range), float(range), float(fov));
    return node_->ack(token, wire::Body::FiducialGeometry, body.Union());
  }
  if (d.kind == Kind::Ranger && sub == uint8_t(wire::RangerReqSub::Geometry)) {
    auto& b = node_->begin();
    auto body = wire::CreateRangerGeometry(b, &pose, &size);
    return node_->ack(token, wire::Body::RangerGeometry, body.Union());
  }
  if (d.kind == Kind::Ranger && sub == uint8_t(wire::RangerReqSub::GetConfig)) {
    const SensorReading& r = sim_.readings(d.robot)[size_t(d.reading)];
    const double last = r.angle_min + r.angle_step * double(r.ranges.empty() ? 0 : r.ranges.size() - 1);
    const double rate = 1.0 / (sim_.cycle_s() * std::max(1, spec->period));
    auto& b = node_->begin();
    auto body = wire::CreateRangerConfig(b, float(r.angle_min), float(last), float(r.angle_step),
                                         float(min_range), float(range), 0.0f, float(rate));
    return node_->ack(token, wire::Body::RangerConfig, body.Union());
  }
  if (d.kind == Kind::Ranger && sub == uint8_t(wire::RangerReqSub::SetConfig)) {
    return node_->nack(token, ErrorCode::Unsupported, "a RoboCup sensor's configuration is the robot file's");
  }
  Driver::on_request(d.id, req, token);
}

sim::SimTime RobocupServer::now() const {
  return {sim_.time_s(), uint64_t(std::llround(sim_.time_s() / sim_.cycle_s()))};
}

void RobocupServer::simulation_request(const wire::Message& req, RequestToken token) {
  using Sub = wire::SimulationReqSub;
  switch (Sub(req.header()->subtype())) {
    case Sub::Pause:
    case Sub::Resume:
    case Sub::GetClock:
    case Sub::Step:
    case Sub::SetSpeed:
      return sim::answer_clock_request(*node_, control_, req, token, [this] { return now(); });
    case Sub::GetPose:
    case Sub::SetPose:
      return pose_request(req, Sub(req.header()->subtype()) == Sub::SetPose, token);
    case Sub::Reset:
      // Robots and ball to their kick-off places; the score stays.
      sim_.reset();
      publish();
      return sim::ack_clock(*node_, control_, token, now());
    case Sub::StartPlayer:
    case Sub::StopPlayer:
      return player_request(req, token);
    case Sub::GetGame: {
      auto& b = node_->begin();
      auto body = build_game(b);
      return node_->ack(token, wire::Body::SimGame, body.Union());
    }
    case Sub::Models:
      // The browser viewer's model list (footprints for drawing): not served
      // for RoboCup fields yet.
      return node_->nack(token, ErrorCode::Unsupported, "troupe-robocup does not list its models yet");
  }
  node_->nack(token, ErrorCode::Unsupported, "unknown simulation request");
}

void RobocupServer::pose_request(const wire::Message& req, bool set, RequestToken token) {
  const wire::SimPose* body = req.body_as_SimPose();
  const flatbuffers::String* name = set ? (body ? body->name() : nullptr)
                                        : (req.body_as_SimModel() ? req.body_as_SimModel()->name() : nullptr);
  if (name == nullptr) return node_->nack(token, ErrorCode::BadArgument, "needs a model name");
  const std::string model = name->str();
  const int robot = sim_.find_robot(model);
  if (robot < 0 && model != "ball") {
    return node_->nack(token, ErrorCode::BadArgument,
                       "no model named '" + model + "' (robot names and 'ball')");
  }
  if (set) {
    const wire::Pose2d* p = body->pose();
    if (p == nullptr || !std::isfinite(p->x()) || !std::isfinite(p->y()) || !std::isfinite(p->a())) {
      return node_->nack(token, ErrorCode::BadArgument, "needs a finite pose");
    }
    const wire::Pose2d* v = body->velocity();
    if (v && (!std::isfinite(v->x()) || !std::isfinite(v->y()))) {
      return node_->nack(token, ErrorCode::BadArgument, "needs a finite velocity");
    }
    if (robot >= 0) {
      sim_.place_robot(robot, {p->x(), p->y(), p->a()});
    } else {
      sim_.place_ball({p->x(), p->y()}, v ? Vec2{v->x(), v->y()} : Vec2{});
    }
    return node_->ack(token);
  }
  Pose2 pose;
  Twist vel;
  if (robot >= 0) {
    const RobotInfo info = sim_.robot(robot);
    pose = info.pose;
    vel = info.velocity;
  } else {
    const BallInfo ball = sim_.ball();
    pose = {ball.position.x, ball.position.y, 0};
    vel = {ball.velocity.x, ball.velocity.y, 0};
  }
  auto& b = node_->begin();
  wire::Pose2d p(float(pose.x), float(pose.y), float(pose.a));
  wire::Pose2d v(float(vel.vx), float(vel.vy), float(vel.w));
  auto reply = wire::CreateSimPose(b, b.CreateString(model), &p, &v);
  node_->ack(token, wire::Body::SimPose, reply.Union());
}

void RobocupServer::player_request(const wire::Message& req, RequestToken token) {
  std::string error;
  if (wire::SimulationReqSub(req.header()->subtype()) == wire::SimulationReqSub::StopPlayer) {
    const wire::SimModel* m = req.body_as_SimModel();
    if (m == nullptr || m->name() == nullptr)
      return node_->nack(token, ErrorCode::BadArgument, "needs a robot name");
    if (sim_.find_robot(m->name()->str()) < 0) {
      return node_->nack(token, ErrorCode::BadArgument, "no robot named '" + m->name()->str() + "'");
    }
    sim_.stop_player(m->name()->str());
    return node_->ack(token);
  }
  const wire::SimPlayer* p = req.body_as_SimPlayer();
  if (p == nullptr || p->robot() == nullptr || p->plugin() == nullptr) {
    return node_->nack(token, ErrorCode::BadArgument, "needs a robot and a plugin name");
  }
  Options options("simulation:0 StartPlayer", "");
  if (p->options()) {
    for (const flatbuffers::String* kv : *p->options()) {
      const std::string text = kv ? kv->str() : std::string();
      const size_t eq = text.find('=');
      if (eq == std::string::npos || eq == 0) {
        return node_->nack(token, ErrorCode::BadArgument, "option '" + text + "': expected key=value");
      }
      options.set(text.substr(0, eq), text.substr(eq + 1));
    }
  }
  if (!sim_.start_player(p->robot()->str(), p->plugin()->str(), options, error)) {
    return node_->nack(token, ErrorCode::BadArgument, error);
  }
  node_->ack(token);
}

}  // namespace troupe::robocup
