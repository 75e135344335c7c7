#include "host-sim/troupe_sim/sim_server.h"

#include <cmath>
#include <utility>

#include "runtime/log.h"

namespace troupe::sim {

using wire::ErrorCode;

void SimServer::log_refused(const char* what, RobotId robot, const Pose& value) {
  if (!log_this_one(refused_)) return;
  log_warn("robot '%s': %s (%g, %g, %g) refused: not finite or out of range (%llu refused so far)",
           world_.robot(robot).name.c_str(), what, value.x, value.y, value.a,
           static_cast<unsigned long long>(refused_));
}

SimServer::SimServer(World& world, SimControl& control, int only)
    : SimServer(world, control, Scope{only, 0, false, {}}) {}

SimServer::SimServer(World& world, SimControl& control, Scope scope)
    : world_(world), kickers_(world), control_(control), scope_(std::move(scope)) {}

void SimServer::add(Node& node, Kind kind, RobotId robot, uint32_t index, wire::Interface iface,
                    uint16_t local) {
  const bool world_wide = kind == Kind::Simulation || kind == Kind::Map;
  const uint16_t number = scope_.only >= 0 || world_wide ? 0 : uint16_t(robot - scope_.first_robot);
  const std::string name = world_wide ? std::string() : world_.robot(robot).name;
  if (scope_.first_index && !world_wide) local = uint16_t(local + scope_.first_index(number, iface));
  Device d;
  d.kind = kind;
  d.robot = robot;
  d.index = index;
  d.id = node.add_device(wire::Address(number, uint16_t(iface), local), this, "troupe-sim", name);
  if (first_ == kNoDevice) first_ = d.id;
  devices_.push_back(d);
}

bool SimServer::setup(Node& node, const DriverSetup&, std::string& error) {
  if (world_.robot_count() - scope_.first_robot > 0xFFFF) {
    error =
        "more than 65535 robots cannot be addressed (a robot's number on the wire is 16 bits); "
        "--no-serve runs the world unserved";
    return false;
  }
  for (RobotId r = scope_.first_robot; r < world_.robot_count(); ++r) {
    if (scope_.only >= 0 && r != RobotId(scope_.only)) continue;
    const RobotInfo& info = world_.robot(r);
    if (!scope_.sensors_only) add(node, Kind::Position, r, 0, wire::Interface::Position2d, 0);
    for (uint32_t k = 0; k < info.rangers.count; ++k) {
      add(node, Kind::Ranger, r, info.rangers.first + k, wire::Interface::Ranger, uint16_t(k));
    }
    for (uint32_t k = 0; k < info.blobfinders.count; ++k) {
      add(node, Kind::Blobfinder, r, info.blobfinders.first + k, wire::Interface::Blobfinder, uint16_t(k));
    }
    for (uint32_t k = 0; k < info.fiducials.count; ++k) {
      add(node, Kind::Fiducial, r, info.fiducials.first + k, wire::Interface::Fiducial, uint16_t(k));
    }
    for (uint32_t k = 0; k < info.bumpers.count; ++k) {
      add(node, Kind::Bumper, r, info.bumpers.first + k, wire::Interface::Bumper, uint16_t(k));
    }
    for (uint32_t k = 0; k < info.cameras.count; ++k) {
      add(node, Kind::Camera, r, info.cameras.first + k, wire::Interface::Camera, uint16_t(k));
    }
    for (uint32_t k = 0; k < info.grippers.count; ++k) {
      add(node, Kind::Gripper, r, info.grippers.first + k, wire::Interface::Actuator, uint16_t(k));
    }
    const IndexRange kickers = kickers_.of(r);
    for (uint32_t k = 0; k < kickers.count; ++k) {
      add(node, Kind::Kicker, r, kickers.first + k, wire::Interface::Actuator,
          uint16_t(info.grippers.count + k));
    }
    if (info.has_power && !scope_.sensors_only) add(node, Kind::Power, r, 0, wire::Interface::Power, 0);
  }
  if (scope_.only < 0 && !scope_.sensors_only) {
    add(node, Kind::Simulation, 0, 0, wire::Interface::Simulation, 0);
    add(node, Kind::Map, 0, 0, wire::Interface::Map, 0);
  }
  for (Device& d : devices_) {
    if (d.id == kNoDevice) {
      error = "two devices with one address";
      return false;
    }
    // Sensors already wanted (by controllers) stay wanted.
    if (d.kind == Kind::Ranger) d.pinned = world_.wanted({SensorKind::Ranger, d.index});
    if (d.kind == Kind::Blobfinder) d.pinned = world_.wanted({SensorKind::Blobfinder, d.index});
    if (d.kind == Kind::Fiducial) d.pinned = world_.wanted({SensorKind::Fiducial, d.index});
    if (d.kind == Kind::Bumper) d.pinned = world_.wanted({SensorKind::Bumper, d.index});
    if (d.kind == Kind::Camera) d.pinned = world_.wanted({SensorKind::Camera, d.index});
  }
  return true;
}

const SimServer::Device* SimServer::find(DeviceId id) const {
  if (first_ == kNoDevice || id < first_ || id - first_ >= devices_.size()) return nullptr;
  return &devices_[id - first_];
}

bool SimServer::sync_wanted() {
  bool woke = false;
  for (uint32_t i = 0; i < devices_.size(); ++i) {
    const Device& d = devices_[i];
    SensorKind kind;
    switch (d.kind) {
      case Kind::Ranger:
        kind = SensorKind::Ranger;
        break;
      case Kind::Blobfinder:
        kind = SensorKind::Blobfinder;
        break;
      case Kind::Fiducial:
        kind = SensorKind::Fiducial;
        break;
      case Kind::Bumper:
        kind = SensorKind::Bumper;
        break;
      case Kind::Camera:
        kind = SensorKind::Camera;
        break;
      default:
        continue;
    }
    const bool want = d.pinned || node_->has_readers(d.id);
    if (want != world_.wanted({kind, d.index})) {
      world_.set_wanted({kind, d.index}, want);
      if (want) woken_.push_back(i);
      woke = woke || want;
    }
  }
  return woke;
}

void SimServer::on_command(DeviceId id, const wire::Message& cmd) {
  const Device* d = find(id);
  if (d != nullptr && d->kind == Kind::Gripper) {
    // A gripper opens and closes; other actions (stop, kick, goto) mean
    // nothing to it and are ignored.
    const wire::ActuatorCommand* a = cmd.body_as_ActuatorCommand();
    if (a && a->action() == wire::ActuatorAction::Open) world_.set_gripper(d->index, false);
    if (a && a->action() == wire::ActuatorAction::Close) world_.set_gripper(d->index, true);
    return;
  }
  if (d != nullptr && d->kind == Kind::Kicker) {
    // A kicker kicks; other actions mean nothing to it. A kick while it
    // recovers from the last one does nothing, as on a real robot.
    const wire::ActuatorCommand* a = cmd.body_as_ActuatorCommand();
    if (a && a->action() == wire::ActuatorAction::Kick) kickers_.kick(d->index);
    return;
  }
  if (d == nullptr || d->kind != Kind::Position || !d->motors_on) return;
  Command c;
  if (const wire::Position2dVel* v = cmd.body_as_Position2dVel(); v && v->vel()) {
    c = Command::velocity(v->vel()->x(), v->vel()->y(), v->vel()->a());
  } else if (const wire::Position2dGoto* g = cmd.body_as_Position2dGoto(); g && g->pose()) {
    c = Command::go_to(g->pose()->x(), g->pose()->y(), g->pose()->a());
  } else {
    return;
  }
  // The node refuses non-finite fields before they get here; this guards
  // every other way in.
  if (!world_.command(d->robot, c)) {
    log_refused(c.mode == CommandMode::Velocity ? "velocity command" : "goto command", d->robot, c.value);
  }
}

void SimServer::on_request(DeviceId id, const wire::Message& req, RequestToken token) {
  Device* d = const_cast<Device*>(find(id));
  if (d == nullptr) return node_->nack(token, ErrorCode::NoSuchDevice, "not a simulated device");
  const uint8_t sub = req.header()->subtype();
  switch (d->kind) {
    case Kind::Simulation:
      return answer_simulation_request(*node_, control_, req, token, *this);
    case Kind::Position:
      return position_request(*d, req, token);
    case Kind::Map:
      return map_request(*d, req, token);
    case Kind::Ranger:
      return ranger_request(*d, req, token);
    case Kind::Camera:
      return camera_request(*d, req, token);
    case Kind::Fiducial:
      if (sub == uint8_t(wire::FiducialReqSub::Geometry)) {
        const FiducialDesc& f = world_.fiducial_desc(d->index);
        auto& b = node_->begin();
        wire::Pose3d pose(float(f.pose.x), float(f.pose.y), 0, 0, 0, float(f.pose.a));
        wire::Vec3 size(0, 0, 0);
        auto body = wire::CreateFiducialGeometry(b, &pose, &size, float(f.range_min), float(f.range_max),
                                                 float(f.fov));
        return node_->ack(token, wire::Body::FiducialGeometry, body.Union());
      }
      break;
    case Kind::Bumper:
      if (sub == uint8_t(wire::BumperReqSub::Geometry)) {
        const BumperDesc& bd = world_.bumper_desc(d->index);
        std::vector<wire::BumperDef> defs;
        for (const BumperSegment& s : bd.segments) {
          const Pose p = compose(bd.pose, s.pose);
          defs.emplace_back(wire::Pose2d(float(p.x), float(p.y), float(p.a)), float(s.length), 0.0f);
        }
        auto& b = node_->begin();
        auto body = wire::CreateBumperGeometry(b, b.CreateVectorOfStructs(defs));
        return node_->ack(token, wire::Body::BumperGeometry, body.Union());
      }
      break;
    default:
      break;
  }
  Driver::on_request(id, req, token);
}

void SimServer::position_request(Device& d, const wire::Message& req, RequestToken token) {
  using Sub = wire::Position2dReqSub;
  const RobotDesc& r = world_.desc().robots[d.robot];
  switch (Sub(req.header()->subtype())) {
    case Sub::Geometry: {
      // Centre of the outline's box relative to the centre of rotation.
      double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
      for (const auto& poly : r.polygons) {
        for (Vec2 p : poly) {
          x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
        }
      }
      if (x1 < x0) x0 = -r.size.x / 2, x1 = r.size.x / 2, y0 = -r.size.y / 2, y1 = r.size.y / 2;
      auto& b = node_->begin();
      wire::Pose3d pose(float((x0 + x1) / 2), float((y0 + y1) / 2), 0, 0, 0, 0);
      wire::Vec3 size(float(x1 - x0), float(y1 - y0), float(r.look.height));
      auto body = wire::CreatePosition2dGeometry(b, &pose, &size);
      return node_->ack(token, wire::Body::Position2dGeometry, body.Union());
    }
    case Sub::MotorPower: {
      const wire::Switch* sw = req.body_as_Switch();
      if (sw == nullptr) return node_->nack(token, ErrorCode::BadArgument, "motor power needs a Switch body");
      d.motors_on = sw->on();
      if (!d.motors_on) world_.command(d.robot, Command::velocity(0, 0, 0));
      return node_->ack(token);
    }
    case Sub::SetOdometry: {
      const wire::Position2dSetOdom* set = req.body_as_Position2dSetOdom();
      if (set == nullptr || set->pose() == nullptr)
        return node_->nack(token, ErrorCode::BadArgument, "needs a pose");
      const Pose pose{set->pose()->x(), set->pose()->y(), set->pose()->a()};
      if (!world_.set_odometry(d.robot, pose)) {
        log_refused("odometry", d.robot, pose);
        return node_->nack(token, ErrorCode::BadArgument, "the odometry pose must be finite");
      }
      return node_->ack(token);
    }
    case Sub::ResetOdometry:
      world_.set_odometry(d.robot, {});
      return node_->ack(token);
  }
  Driver::on_request(d.id, req, token);
}

void SimServer::ranger_request(const Device& d, const wire::Message& req, RequestToken token) {
  using Sub = wire::RangerReqSub;
  const RangerDesc& rd = world_.ranger_desc(d.index);
  double range_min = 1e9, range_max = 0;
  for (const TransducerDesc& t : rd.transducers) {
    range_min = std::min(range_min, t.range_min);
    range_max = std::max(range_max, t.range_max);
  }
  if (rd.transducers.empty()) range_min = 0;
  switch (Sub(req.header()->subtype())) {
    case Sub::Geometry: {
      std::vector<wire::Pose3d> elements;
      for (const TransducerDesc& t : rd.transducers) {
        elements.emplace_back(float(t.pose.x), float(t.pose.y), 0.0f, 0.0f, 0.0f, float(t.pose.a));
      }
      auto& b = node_->begin();
      wire::Pose3d pose(float(rd.pose.x), float(rd.pose.y), 0, 0, 0, float(rd.pose.a));
      wire::Vec3 size(float(rd.size.x), float(rd.size.y), 0);
      auto body = wire::CreateRangerGeometry(b, &pose, &size, b.CreateVectorOfStructs(elements));
      return node_->ack(token, wire::Body::RangerGeometry, body.Union());
    }
    case Sub::GetConfig: {
      float min_angle = 0, max_angle = 0, res = 0;
      if (rd.transducers.size() == 1 && rd.transducers[0].samples > 1) {
        const TransducerDesc& t = rd.transducers[0];
        min_angle = float(t.pose.a - t.fov / 2);
        max_angle = float(t.pose.a + t.fov / 2);
        res = float(t.fov / (t.samples - 1));
      }
      auto& b = node_->begin();
      auto body = wire::CreateRangerConfig(b, min_angle, max_angle, res, float(range_min), float(range_max),
                                           0.0f, float(1.0 / world_.interval()));
      return node_->ack(token, wire::Body::RangerConfig, body.Union());
    }
    case Sub::SetConfig:
      return node_->nack(token, ErrorCode::Unsupported,
                         "a simulated ranger's configuration is the world file's");
    case Sub::Power:
      return node_->ack(token);
  }
  Driver::on_request(d.id, req, token);
}

bool SimServer::get_pose(const std::string& name, Pose& pose, bool& has_velocity, Pose&, std::string& error) {
  has_velocity = false;
  if (auto robot = world_.find_robot(name)) {
    pose = world_.state(*robot).pose;
    return true;
  }
  for (const StaticDesc& s : world_.desc().statics) {
    if (s.name != name || s.name.empty()) continue;
    pose = s.pose;
    return true;
  }
  error = "no model named '" + name + "'";
  return false;
}

bool SimServer::set_pose(const std::string& name, const Pose& pose, const Pose*, std::string& error) {
  if (auto robot = world_.find_robot(name)) {
    if (!world_.set_pose(*robot, pose)) {
      log_refused("teleport", *robot, pose);
      error = "the pose must be finite, |x| and |y| at most 1e6 m";
      return false;
    }
    world_.refresh_sensors();
    return true;
  }
  for (const StaticDesc& s : world_.desc().statics) {
    if (s.name == name && !s.name.empty()) {
      error = "'" + name + "' is a static model; it cannot move";
      return false;
    }
  }
  error = "no model named '" + name + "'";
  return false;
}

}  // namespace troupe::sim
