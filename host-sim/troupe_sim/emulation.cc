#include "host-sim/troupe_sim/emulation.h"

#include <cctype>

namespace troupe::sim {
namespace {

bool all_digits(const std::string& s) {
  if (s.empty() || s.size() > 9) return false;
  for (char c : s) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  }
  return true;
}

// The robot a spec names: its name first (a robot may be called "7"), then
// its number.
bool find_robot(const World& world, const std::string& text, RobotId& out, std::string& error) {
  if (auto id = world.find_robot(text)) {
    out = *id;
    return true;
  }
  if (all_digits(text) && std::stoul(text) < world.robot_count()) {
    out = RobotId(std::stoul(text));
    return true;
  }
  error = "no robot '" + text + "' in the world (robots: ";
  for (RobotId r = 0; r < world.robot_count() && r < 8; ++r) error += (r ? ", " : "") + world.robot(r).name;
  if (world.robot_count() > 8) error += ", ...";
  error +=
      world.robot_count() == 0 ? "none)" : "; or a number below " + std::to_string(world.robot_count()) + ")";
  return false;
}

}  // namespace

const char* emulated_kind_name(EmulatedKind kind) {
  return kind == EmulatedKind::P2os ? "p2os" : "sicklms200";
}

bool Emulation::add(World& world, const std::string& spec, std::string& error) {
  const std::string where = "--emulate " + spec + ": ";
  const size_t eq = spec.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size()) {
    error = where + "expected ROBOT=DEVICE[,DEVICE], e.g. r0=p2os,sicklms200";
    return false;
  }
  Robot robot;
  if (!find_robot(world, spec.substr(0, eq), robot.id, error)) {
    error = where + error;
    return false;
  }
  robot.name = world.robot(robot.id).name;
  for (const Robot& r : robots_) {
    if (r.id == robot.id) {
      error = where + "robot " + robot.name + " is already emulated; name all its devices in one --emulate";
      return false;
    }
  }
  bool p2os = false, sick = false;
  for (size_t at = eq + 1; at <= spec.size();) {
    size_t comma = spec.find(',', at);
    if (comma == std::string::npos) comma = spec.size();
    const std::string device = spec.substr(at, comma - at);
    at = comma + 1;
    bool* flag = device == "p2os" ? &p2os : device == "sicklms200" ? &sick : nullptr;
    if (device == "odrive") {
      error =
          where + "ODrive axes on a CAN bus are not emulated by troupe-sim yet (devices: p2os, sicklms200)";
      return false;
    }
    if (flag == nullptr) {
      error = where + "unknown device '" + device + "' (devices: p2os, sicklms200)";
      return false;
    }
    if (*flag) {
      error = where + "device " + device + " named twice";
      return false;
    }
    *flag = true;
  }
  if (sick) {
    std::optional<uint32_t> laser = find_laser(world, robot.id);
    if (!laser) {
      error = where + "robot " + robot.name + " has no laser (a ranger with one sensor of several samples)";
      return false;
    }
    robot.laser = std::make_unique<SimLaser>(world, *laser);
    robot.sick =
        std::make_unique<emulators::SickEmulator>(emulators::SickEmulator::Config{}, robot.laser.get());
  }
  if (p2os) {
    robot.body = std::make_unique<SimPioneerBody>(world, robot.id);
    emulators::PioneerEmulator::Config config;
    config.name = robot.name;
    robot.pioneer = std::make_unique<emulators::PioneerEmulator>(config, robot.body.get());
  }
  robots_.push_back(std::move(robot));
  return true;
}

bool Emulation::open(const std::string& links_dir, std::string& error) {
  for (Robot& r : robots_) {
    auto link = [&](EmulatedKind kind) {
      return links_dir.empty() ? std::string() : links_dir + "/" + r.name + "-" + emulated_kind_name(kind);
    };
    if (r.pioneer && !r.pioneer->open(link(EmulatedKind::P2os), error)) return false;
    if (r.sick && !r.sick->open(link(EmulatedKind::SickLms200), error)) return false;
  }
  return true;
}

void Emulation::step(uint64_t now_us) {
  for (Robot& r : robots_) {
    if (r.pioneer) r.pioneer->step(now_us);
    if (r.sick) r.sick->step(now_us);
  }
}

std::vector<Emulation::Device> Emulation::devices() const {
  std::vector<Device> out;
  for (const Robot& r : robots_) {
    if (r.pioneer) out.push_back({r.id, r.name, EmulatedKind::P2os, r.pioneer->path()});
    if (r.sick) out.push_back({r.id, r.name, EmulatedKind::SickLms200, r.sick->path()});
  }
  return out;
}

std::string Emulation::info() const {
  std::string text;
  for (const Device& d : devices()) {
    text += d.robot_name + " " + emulated_kind_name(d.kind) + " " + d.path + "\n";
  }
  return text;
}

}  // namespace troupe::sim
