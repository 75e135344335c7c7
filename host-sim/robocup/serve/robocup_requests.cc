// Requests to the served RoboCup devices: motor power, sensor geometry;
// simulation:0 goes to the one handler (robocup_models.cc).
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
      return sim::answer_simulation_request(*node_, control_, req, token, *this);
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

}  // namespace troupe::robocup
