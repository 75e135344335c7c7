// What `troupe cmd` and `troupe req` understand: a table from (interface,
// kind, verb) to a message. A new verb is one row and, when it has
// arguments, one small body builder.
#include <cmath>
#include <cstdlib>
#include <span>
#include <vector>

#include "wire/cli/verbs.h"

namespace troupe::cli {
namespace {

using wire::Body;
using Builder = flatbuffers::FlatBufferBuilder;
using Args = std::span<const std::string>;

// strtof reads "nan" and "inf" (and turns 1e39 into inf): none of them is
// a value any field takes.
bool number(const std::string& text, float& out) {
  char* end = nullptr;
  out = strtof(text.c_str(), &end);
  return end != text.c_str() && *end == '\0' && std::isfinite(out);
}

bool numbers(Args args, float* out, size_t n, std::string& error) {
  for (size_t i = 0; i < n; ++i) {
    if (!number(args[i], out[i])) {
      error = "'" + args[i] + "' is not a finite number";
      return false;
    }
  }
  return true;
}

bool on_off(Args args, bool& on, std::string& error) {
  if (args[0] == "on" || args[0] == "1") return on = true, true;
  if (args[0] == "off" || args[0] == "0") return on = false, true;
  error = "want on or off, not '" + args[0] + "'";
  return false;
}

bool none(Builder&, Args, Built&, std::string&) { return true; }

bool pos_vel(Builder& b, Args a, Built& out, std::string& e) {
  float v[3];
  if (!numbers(a, v, 3, e)) return false;
  wire::Pose2d vel(v[0], v[1], v[2]);
  out = {Body::Position2dVel, wire::CreatePosition2dVel(b, &vel).Union()};
  return true;
}

bool pos_goto(Builder& b, Args a, Built& out, std::string& e) {
  float v[3];
  if (!numbers(a, v, 3, e)) return false;
  wire::Pose2d pose(v[0], v[1], v[2]);
  out = {Body::Position2dGoto, wire::CreatePosition2dGoto(b, &pose).Union()};
  return true;
}

bool pos_setodom(Builder& b, Args a, Built& out, std::string& e) {
  float v[3];
  if (!numbers(a, v, 3, e)) return false;
  wire::Pose2d pose(v[0], v[1], v[2]);
  out = {Body::Position2dSetOdom, wire::CreatePosition2dSetOdom(b, &pose).Union()};
  return true;
}

bool switch_body(Builder& b, Args a, Built& out, std::string& e) {
  bool on = false;
  if (!on_off(a, on, e)) return false;
  out = {Body::Switch, wire::CreateSwitch(b, on).Union()};
  return true;
}

template <wire::ActuatorAction kAction>
bool actuator(Builder& b, Args a, Built& out, std::string& e) {
  float value = 0;
  if (!a.empty() && !numbers(a, &value, 1, e)) return false;
  out = {Body::ActuatorCommand, wire::CreateActuatorCommand(b, kAction, value).Union()};
  return true;
}

bool loc_setpose(Builder& b, Args a, Built& out, std::string& e) {
  float v[6] = {0, 0, 0, 0.5f, 0.5f, 0.3f};
  if (!numbers(a, v, a.size(), e)) return false;
  wire::Pose2d mean(v[0], v[1], v[2]);
  wire::Cov2d cov(v[3] * v[3], 0, 0, v[4] * v[4], 0, v[5] * v[5]);
  out = {Body::LocalizeSetPose, wire::CreateLocalizeSetPose(b, &mean, &cov).Union()};
  return true;
}

bool map_tile(Builder& b, Args a, Built& out, std::string& e) {
  float v[4];
  if (!numbers(a, v, 4, e)) return false;
  out = {Body::MapTileRequest,
         wire::CreateMapTileRequest(b, uint32_t(v[0]), uint32_t(v[1]), uint32_t(v[2]), uint32_t(v[3])).Union()};
  return true;
}

bool sim_step(Builder& b, Args a, Built& out, std::string& e) {
  float n = 1;
  if (!a.empty() && !numbers(a, &n, 1, e)) return false;
  if (n < 1) {
    e = "step count must be at least 1";
    return false;
  }
  out = {Body::SimStep, wire::CreateSimStep(b, uint32_t(n)).Union()};
  return true;
}

bool sim_speed(Builder& b, Args a, Built& out, std::string& e) {
  float s = 0;
  if (!numbers(a, &s, 1, e)) return false;
  out = {Body::SimSpeed, wire::CreateSimSpeed(b, s).Union()};
  return true;
}

bool sim_model(Builder& b, Args a, Built& out, std::string&) {
  out = {Body::SimModel, wire::CreateSimModel(b, b.CreateString(a[0])).Union()};
  return true;
}

bool sim_setpose(Builder& b, Args a, Built& out, std::string& e) {
  float v[3];
  if (!numbers(a.subspan(1), v, 3, e)) return false;
  wire::Pose2d pose(v[0], v[1], v[2]);
  out = {Body::SimPose, wire::CreateSimPose(b, b.CreateString(a[0]), &pose).Union()};
  return true;
}

bool sim_start_player(Builder& b, Args a, Built& out, std::string& e) {
  std::vector<flatbuffers::Offset<flatbuffers::String>> options;
  for (const std::string& kv : a.subspan(2)) {
    if (kv.find('=') == std::string::npos || kv[0] == '=') {
      e = "'" + kv + "' is not key=value";
      return false;
    }
    options.push_back(b.CreateString(kv));
  }
  auto robot = b.CreateString(a[0]);
  auto plugin = b.CreateString(a[1]);
  out = {Body::SimPlayer, wire::CreateSimPlayer(b, robot, plugin, b.CreateVector(options)).Union()};
  return true;
}

bool opaque(Builder& b, Args a, Built& out, std::string& e) {
  std::vector<uint8_t> bytes;
  const std::string& hex = a[0];
  if (hex.size() % 2 != 0) {
    e = "hex bytes need an even number of digits";
    return false;
  }
  for (size_t i = 0; i < hex.size(); i += 2) {
    char* end = nullptr;
    std::string pair = hex.substr(i, 2);
    long v = strtol(pair.c_str(), &end, 16);
    if (*end != '\0') {
      e = "'" + pair + "' is not a hex byte";
      return false;
    }
    bytes.push_back(uint8_t(v));
  }
  out = {Body::OpaqueBytes, wire::CreateOpaqueBytes(b, b.CreateVector(bytes)).Union()};
  return true;
}

using I = wire::Interface;
using K = wire::Kind;
constexpr K kCmd = K::Command;
constexpr K kReq = K::Request;

template <typename E>
constexpr uint8_t sub(E e) {
  return uint8_t(e);
}

const Verb kVerbs[] = {
    {I::Position2d, kCmd, "vel", "VX VY VA", "velocity: m/s forward, m/s left, rad/s", sub(wire::Position2dCmdSub::Vel), 3, 3, pos_vel},
    {I::Position2d, kCmd, "goto", "X Y A", "drive to a pose: m, m, rad", sub(wire::Position2dCmdSub::Goto), 3, 3, pos_goto},
    {I::Position2d, kReq, "geometry", "", "size and body offset", sub(wire::Position2dReqSub::Geometry), 0, 0, none},
    {I::Position2d, kReq, "motor", "on|off", "motor power", sub(wire::Position2dReqSub::MotorPower), 1, 1, switch_body},
    {I::Position2d, kReq, "setodom", "X Y A", "set odometry: m, m, rad", sub(wire::Position2dReqSub::SetOdometry), 3, 3, pos_setodom},
    {I::Position2d, kReq, "resetodom", "", "odometry back to 0, 0, 0", sub(wire::Position2dReqSub::ResetOdometry), 0, 0, none},
    {I::Ranger, kReq, "geometry", "", "sensor and transducer poses", sub(wire::RangerReqSub::Geometry), 0, 0, none},
    {I::Ranger, kReq, "config", "", "angles, ranges, frequency", sub(wire::RangerReqSub::GetConfig), 0, 0, none},
    {I::Ranger, kReq, "power", "on|off", "sensor power", sub(wire::RangerReqSub::Power), 1, 1, switch_body},
    {I::Bumper, kReq, "geometry", "", "bumper segments", sub(wire::BumperReqSub::Geometry), 0, 0, none},
    {I::Fiducial, kReq, "geometry", "", "sensor pose, range and field of view", sub(wire::FiducialReqSub::Geometry), 0, 0, none},
    {I::Actuator, kCmd, "open", "", "open the gripper", sub(wire::ActuatorCmdSub::Action), 0, 0, actuator<wire::ActuatorAction::Open>},
    {I::Actuator, kCmd, "close", "", "close the gripper", sub(wire::ActuatorCmdSub::Action), 0, 0, actuator<wire::ActuatorAction::Close>},
    {I::Actuator, kCmd, "stop", "", "stop moving", sub(wire::ActuatorCmdSub::Action), 0, 0, actuator<wire::ActuatorAction::Stop>},
    {I::Actuator, kCmd, "kick", "[SPEED]", "kick, ball speed m/s", sub(wire::ActuatorCmdSub::Action), 0, 1, actuator<wire::ActuatorAction::Kick>},
    {I::Actuator, kCmd, "goto", "POS", "move to a position, m or rad", sub(wire::ActuatorCmdSub::Action), 1, 1, actuator<wire::ActuatorAction::Goto>},
    {I::Localize, kReq, "setpose", "X Y A [SX SY SA]", "track from a pose (m, rad; std devs)", sub(wire::LocalizeReqSub::SetPose), 3, 6, loc_setpose},
    {I::Localize, kReq, "global", "", "restart global localization", sub(wire::LocalizeReqSub::Global), 0, 0, none},
    {I::Map, kReq, "info", "", "size, resolution, origin", sub(wire::MapReqSub::Info), 0, 0, none},
    {I::Map, kReq, "tile", "COL ROW W H", "a block of cells", sub(wire::MapReqSub::Tile), 4, 4, map_tile},
    {I::Simulation, kReq, "pause", "", "stop simulated time", sub(wire::SimulationReqSub::Pause), 0, 0, none},
    {I::Simulation, kReq, "resume", "", "run again", sub(wire::SimulationReqSub::Resume), 0, 0, none},
    {I::Simulation, kReq, "step", "[N]", "run N steps while paused", sub(wire::SimulationReqSub::Step), 0, 1, sim_step},
    {I::Simulation, kReq, "speed", "X", "multiple of real time, 0: fastest", sub(wire::SimulationReqSub::SetSpeed), 1, 1, sim_speed},
    {I::Simulation, kReq, "getpose", "MODEL", "ground-truth pose", sub(wire::SimulationReqSub::GetPose), 1, 1, sim_model},
    {I::Simulation, kReq, "setpose", "MODEL X Y A", "teleport: m, m, rad", sub(wire::SimulationReqSub::SetPose), 4, 4, sim_setpose},
    {I::Simulation, kReq, "reset", "", "every model back to its start", sub(wire::SimulationReqSub::Reset), 0, 0, none},
    {I::Simulation, kReq, "clock", "", "simulated time and speed", sub(wire::SimulationReqSub::GetClock), 0, 0, none},
    {I::Simulation, kReq, "start", "ROBOT PLUGIN [KEY=VALUE]...", "start a player plugin on a robot", sub(wire::SimulationReqSub::StartPlayer), 2, 64, sim_start_player},
    {I::Simulation, kReq, "stop", "ROBOT", "stop the robot's player plugin", sub(wire::SimulationReqSub::StopPlayer), 1, 1, sim_model},
    {I::Simulation, kReq, "game", "", "score and game state", sub(wire::SimulationReqSub::GetGame), 0, 0, none},
    {I::Opaque, kCmd, "bytes", "HEX", "arbitrary bytes", sub(wire::OpaqueSub::Bytes), 1, 1, opaque},
    {I::Opaque, kReq, "bytes", "HEX", "arbitrary bytes", sub(wire::OpaqueSub::Bytes), 1, 1, opaque},
};

}  // namespace

const Verb* find_verb(wire::Interface iface, wire::Kind kind, const std::string& name) {
  for (const Verb& v : kVerbs) {
    if (v.iface == iface && v.kind == kind && name == v.name) return &v;
  }
  return nullptr;
}

std::string verb_list(wire::Interface iface, wire::Kind kind, bool names_only) {
  std::string out;
  for (const Verb& v : kVerbs) {
    if (v.iface != iface || v.kind != kind) continue;
    if (names_only) {
      out += out.empty() ? "" : ", ";
      out += v.name;
      continue;
    }
    out += "  ";
    out += v.name;
    if (*v.args) out += std::string(" ") + v.args;
    out += "  (" + std::string(v.help) + ")\n";
  }
  return out;
}

}  // namespace troupe::cli
