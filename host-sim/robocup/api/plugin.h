// The contract of RoboCup sensor, motion and player plugins. A plugin is a
// shared library <name>.so of the project's one plugin ABI
// (host-sim/plugin/plugin_abi.h): it exports
//
//   TROUPE_PLUGIN_EXPORT const TroupePluginInfo* troupe_plugin_v1() {
//     return troupe::robocup::plugin_info<SensorPlugin, MyCamera>(PluginKind::Sensor, "my_camera");
//   }
//
// The simulator finds the library on the plugin path, checks the ABI, the
// kind and this interface's version (kPluginApiVersion), and makes one
// instance per use (a sensor on a robot, a robot's motion model, a running
// player). Every instance is configured from its options first; a false
// answer names the problem and the simulator goes on without that instance.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "host-sim/plugin/plugin_abi.h"
#include "host-sim/robocup/api/options.h"
#include "host-sim/robocup/api/sensor_data.h"
#include "host-sim/robocup/api/world_view.h"
#include "runtime/random.h"

namespace troupe::robocup {

/// The version of the interfaces below (TroupePluginInfo::interface_version).
/// 2: Rng became the project's counter-based RandomSequence.
inline constexpr uint32_t kPluginApiVersion = 2;

enum class PluginKind : uint32_t {
  Sensor = TROUPE_PLUGIN_SENSOR,
  Motion = TROUPE_PLUGIN_MOTION,
  Player = TROUPE_PLUGIN_PLAYER,
};

/// The random generator every plugin instance is handed: seeded from the
/// world's seed, the robot and the instance, so a run repeats exactly, with
/// the same numbers on every platform (the project's one generator).
using Rng = RandomSequence;

// ---- Sensors ----------------------------------------------------------------

struct SensorContext {
  /// The robot carrying the sensor.
  int robot = -1;
  /// Where the sensor sits on the robot (robot frame: m, rad) and its
  /// height above the floor, m.
  Pose2 mount;
  double mount_z = 0;
  Rng* rng = nullptr;
};

class SensorPlugin {
 public:
  virtual ~SensorPlugin() = default;
  /// Reads the options; false with `error` on a bad or unknown one.
  virtual bool configure(Options& options, std::string& error) = 0;
  /// Measures the world now into `out` (name, model and time are filled in
  /// by the simulator).
  virtual void sense(const WorldView& world, const SensorContext& context, SensorReading& out) = 0;
};

// ---- Motion -----------------------------------------------------------------

/// A velocity command in the robot frame: m/s forward, m/s left, rad/s.
struct MotionCommand {
  double vx = 0, vy = 0, w = 0;
};

class MotionPlugin {
 public:
  virtual ~MotionPlugin() = default;
  virtual bool configure(Options& options, std::string& error) = 0;
  /// The robot-frame velocity of the robot's origin (m/s, m/s, rad/s) for
  /// the next `dt_s` seconds, given the command and the velocity the robot
  /// has now (after any collision changed it).
  virtual Twist drive(const MotionCommand& command, const Twist& current, double dt_s) = 0;
};

// ---- Players ----------------------------------------------------------------

/// A message on the players' broadcast channel.
struct Message {
  /// The sending robot's name and team.
  std::string from;
  Team team = Team::Blue;
  /// When it was sent, s.
  double time_s = 0;
  std::string data;
};

struct PlayerContext {
  std::string_view robot;
  int index = -1;
  Team team = Team::Blue;
  Rng* rng = nullptr;
};

struct PlayerInput {
  /// The robot's sensor readings of the last cycle.
  std::span<const SensorReading> readings;
  /// Messages every player sent in the last cycle, its own included (check
  /// Message::from).
  std::span<const Message> inbox;
  /// True when the kicker is at rest and a kick would fire.
  bool kicker_ready = false;
};

struct PlayerOutput {
  MotionCommand command;
  /// Fire the kicker (ignored while it is not at rest).
  bool kick = false;
  /// Messages to every player, delivered next cycle.
  std::vector<std::string> broadcast;
};

class PlayerPlugin {
 public:
  virtual ~PlayerPlugin() = default;
  virtual bool configure(Options& options, std::string& error) = 0;
  /// Called when the player starts on its robot.
  virtual void start(WorldControl& /*world*/, const PlayerContext& /*context*/) {}
  /// Sense and act, once per cycle.
  virtual void act(WorldControl& world, const PlayerContext& context, const PlayerInput& input,
                   PlayerOutput& output) = 0;
};

// ---- The entry point --------------------------------------------------------

/// The TroupePluginInfo of `Impl`, which implements `Interface`.
template <class Interface, class Impl>
const TroupePluginInfo* plugin_info(PluginKind kind, const char* name) {
  static const TroupePluginInfo info{TROUPE_PLUGIN_ABI_VERSION, uint32_t(kind), kPluginApiVersion, name,
                                     [](const char*) -> void* { return static_cast<Interface*>(new Impl()); },
                                     [](void* p) { delete static_cast<Interface*>(p); }};
  return &info;
}

}  // namespace troupe::robocup
