#include "host-sim/robocup/serve/robocup_server.h"

namespace troupe::robocup {

ReadingKind served_kind(const PluginSpec& sensor) {
  if (sensor.plugin == "odometry") return ReadingKind::Odometry;
  if (sensor.plugin == "ultrasonic") return ReadingKind::Ranges;
  if (sensor.plugin == "laser") {
    Options options = sensor.options;  // text() marks keys used: work on a copy
    return options.text("mode", "raw") == "iconic" ? ReadingKind::Detections : ReadingKind::Ranges;
  }
  // Cameras, omni-vision and plugins we do not know report detections.
  return ReadingKind::Detections;
}

RobocupServer::RobocupServer(Simulation& sim, sim::SimControl& control) : sim_(sim), control_(control) {}

void RobocupServer::add(Node& node, Kind kind, int robot, int reading, wire::Interface iface, uint16_t index,
                        const std::string& model) {
  Device d;
  d.kind = kind;
  d.robot = robot;
  d.reading = reading;
  const std::string robot_name =
      kind == Kind::Simulation ? std::string() : sim_.spec().robots[size_t(robot)].name;
  d.id = node.add_device(wire::Address(uint16_t(robot), uint16_t(iface), index), this, model, robot_name);
  if (first_ == kNoDevice) first_ = d.id;
  devices_.push_back(d);
}

bool RobocupServer::setup(Node& node, const DriverSetup&, std::string& error) {
  if (sim_.robot_count() > 0xFFFF) {
    error = "more than 65535 robots cannot be addressed";
    return false;
  }
  for (int r = 0; r < sim_.robot_count(); ++r) {
    const RobotEntry& entry = sim_.spec().robots[size_t(r)];
    const std::span<const SensorReading> readings = sim_.readings(r);
    int odometry = -1;
    std::string odometry_name = "base";
    for (size_t k = 0; k < readings.size() && odometry < 0; ++k) {
      if (readings[k].model == "odometry") odometry = int(k), odometry_name = readings[k].name;
    }
    add(node, Kind::Position, r, odometry, wire::Interface::Position2d, 0, "robocup/" + odometry_name);
    if (entry.spec.has_kicker) add(node, Kind::Kicker, r, -1, wire::Interface::Actuator, 0, "robocup/kicker");
    uint16_t fiducials = 0, rangers = 0;
    for (size_t k = 0; k < readings.size(); ++k) {
      const PluginSpec* spec = nullptr;
      for (const PluginSpec& s : entry.spec.sensors) {
        if (s.name == readings[k].name) spec = &s;
      }
      if (spec == nullptr || int(k) == odometry) continue;
      const std::string model = "robocup/" + readings[k].name;
      switch (served_kind(*spec)) {
        case ReadingKind::Detections:
          add(node, Kind::Fiducial, r, int(k), wire::Interface::Fiducial, fiducials++, model);
          break;
        case ReadingKind::Ranges:
          add(node, Kind::Ranger, r, int(k), wire::Interface::Ranger, rangers++, model);
          break;
        case ReadingKind::Odometry:
          break;  // a second odometry sensor: position2d carries the first
      }
    }
  }
  add(node, Kind::Simulation, 0, -1, wire::Interface::Simulation, 0, "troupe-sim");
  for (const Device& d : devices_) {
    if (d.id == kNoDevice) {
      error = "two devices with one address";
      return false;
    }
  }
  return true;
}

uint16_t RobocupServer::device_count(int robot, wire::Interface iface) const {
  const auto kind_of = [](Kind k) {
    switch (k) {
      case Kind::Position:
        return wire::Interface::Position2d;
      case Kind::Kicker:
        return wire::Interface::Actuator;
      case Kind::Fiducial:
        return wire::Interface::Fiducial;
      case Kind::Ranger:
        return wire::Interface::Ranger;
      case Kind::Simulation:
        break;
    }
    return wire::Interface::Simulation;
  };
  uint16_t n = 0;
  for (const Device& d : devices_) {
    if (d.kind != Kind::Simulation && d.robot == robot && kind_of(d.kind) == iface) ++n;
  }
  return n;
}

RobocupServer::Device* RobocupServer::find(DeviceId id) {
  if (first_ == kNoDevice || id < first_ || id - first_ >= devices_.size()) return nullptr;
  return &devices_[id - first_];
}

const PluginSpec* RobocupServer::sensor_spec(const Device& d) const {
  if (d.reading < 0) return nullptr;
  const std::span<const SensorReading> readings = sim_.readings(d.robot);
  for (const PluginSpec& s : sim_.spec().robots[size_t(d.robot)].spec.sensors) {
    if (s.name == readings[size_t(d.reading)].name) return &s;
  }
  return nullptr;
}

void RobocupServer::on_command(DeviceId id, const wire::Message& cmd) {
  const Device* d = find(id);
  if (d == nullptr) return;
  if (d->kind == Kind::Position && d->motors_on) {
    // Commands have no reply: one sent while a player drives the robot is
    // dropped by the simulation (the player's command wins).
    if (const wire::Position2dVel* v = cmd.body_as_Position2dVel(); v && v->vel()) {
      sim_.command(d->robot, {v->vel()->x(), v->vel()->y(), v->vel()->a()});
    }
  } else if (d->kind == Kind::Kicker) {
    const wire::ActuatorCommand* a = cmd.body_as_ActuatorCommand();
    if (a && a->action() == wire::ActuatorAction::Kick) sim_.kick(d->robot);
  }
}

}  // namespace troupe::robocup
