// World files: the physics settings, the field, the ball, the referee and
// the robots (each with a team, a start pose and an optional player
// plugin). They are Stage world files; README.md ("World files") has the
// models:
//
//   interval_sim 10   restitution 0.5   friction 0.2   seed 1
//   plugin_path "plugins"
//   include "robots/keeper.inc"            # define keeper robocup_robot ( ... )
//   robocup_field ( length 9 width 5 )
//   ball ( radius 0.11 mass 0.43 deceleration 0.4 pose [0 0 0 0] )
//   referee ( goal_pause 1 )
//   keeper ( name "blue1" team "blue" pose [-4.2 0 0 0] player ( plugin "goalkeeper" policy "block" ) )
#pragma once

#include <string>
#include <vector>

#include "host-sim/robocup/game/field.h"
#include "host-sim/robocup/game/referee.h"
#include "host-sim/robocup/game/robot_spec.h"
#include "host-sim/robocup/physics/world.h"

namespace troupe::robocup {

struct BallSpec {
  /// m, kg.
  double radius = 0.11, mass = 0.43;
  /// Rolling friction on the carpet, m/s^2.
  double deceleration = 0.4;
  /// Kick-off spot, world, m.
  Vec2 start;
};

struct RobotEntry {
  std::string name;
  Team team = Team::Blue;
  /// Kick-off pose, world: m, m, rad.
  Pose2 start;
  RobotSpec spec;
  bool has_player = false;
  PluginSpec player;
  /// Stage sensor models it carries (Statement::stage_sensors); null: none.
  std::shared_ptr<const sim::RobotDesc> stage_sensors;
  std::string where;
};

struct WorldSpec {
  std::string file;
  WorldDef physics;
  uint64_t seed = 1;
  /// Folders searched for plugins before the default ones.
  std::vector<std::string> plugin_path;
  FieldSpec field;
  BallSpec ball;
  RefereeSpec referee;
  std::vector<RobotEntry> robots;
};

bool read_world(const std::vector<Statement>& statements, const std::string& file, WorldSpec& out,
                std::string& error);
/// A Stage world file with RoboCup models (statement.h has the mapping),
/// read by the one loader (world_load.h); false for a world without them.
bool load_world_file(const std::string& path, WorldSpec& out, std::string& error);
/// The same from text, named `file` (includes resolve next to it).
bool parse_world_text(const std::string& text, const std::string& file, WorldSpec& out, std::string& error);

}  // namespace troupe::robocup
