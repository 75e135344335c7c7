// Robot configuration files: a robot's geometry from primitives, its mass,
// its kicker (states of different geometry), its motion plugin and its
// sensor plugins. README.md ("Robot files") has the full syntax:
//
//   mass 20 inertia=0
//   shape rect length=0.45 width=0.4 z=0,0.6
//   kicker direction=0 reach=0.03 {
//     state rest { shape rect x=0.24 length=0.03 width=0.3 z=0,0.12 }
//     state kick accel=250 contact=0.02 hold=0.3 next=rest { shape ... }
//   }
//   motion diff_drive max_speed=2 accel=2
//   sensor omnivision name=omni range=5 z=0.6
#pragma once

#include <string>
#include <vector>

#include "host-sim/robocup/api/options.h"
#include "host-sim/robocup/game/statement.h"
#include "host-sim/robocup/physics/shape.h"

namespace troupe::robocup {

/// One state of a kicker: its plate's geometry and what entering it does.
struct KickerState {
  std::string name;
  /// Robot frame; tagged kKickerShapeTag.
  std::vector<Shape> shapes;
  /// Acceleration given to a ball touching the plate when this state is
  /// entered, m/s^2, over `contact_s` s: the ball gains accel * contact
  /// m/s along the kick direction.
  double accel = 0, contact_s = 0.02;
  /// Time in this state before moving to `next`, s; 0: stays.
  double hold_s = 0;
  std::string next;
  /// Index of `next` in the kicker's states (-1: none).
  int next_index = -1;
};

/// A kicker: its first state is the rest state; a kick request moves a
/// kicker at rest into its second state.
struct KickerSpec {
  std::vector<KickerState> states;
  /// Kick direction in the robot frame, rad.
  double direction = 0;
  /// A ball within this gap of the plate counts as touching it, m.
  double reach = 0.03;
};

inline constexpr uint32_t kKickerShapeTag = 1;

/// A plugin named in a file, with its options (the reserved keys name, x,
/// y, a, z and period are taken out).
struct PluginSpec {
  std::string plugin;
  /// Instance name (sensors: defaults to the plugin's name).
  std::string name;
  Options options;
  /// Sensor mount: robot frame (m, rad) and height, m.
  Pose2 mount;
  double mount_z = 0.3;
  /// Sensors: measure every `period` cycles.
  int period = 1;
  /// "file:line".
  std::string where;
};

struct RobotSpec {
  std::string file;
  /// kg; kg m^2 about the centre of mass (0: from the shapes).
  double mass = 20, inertia = 0;
  std::vector<Shape> shapes;
  bool has_kicker = false;
  KickerSpec kicker;
  bool has_motion = false;
  PluginSpec motion;
  std::vector<PluginSpec> sensors;
};

/// A `shape` statement: rect, circle, ellipse, triangle or polygon.
bool read_shape(const Statement& statement, Shape& out, std::string& error);
/// A plugin statement (`motion NAME ...`, `sensor NAME ...`, `player NAME
/// ...`): the plugin's name first, then its options.
bool read_plugin(const Statement& statement, PluginSpec& out, std::string& error);
bool read_robot(const std::vector<Statement>& statements, const std::string& file, RobotSpec& out,
                std::string& error);

}  // namespace troupe::robocup
