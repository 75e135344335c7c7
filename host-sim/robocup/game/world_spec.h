// World files: the physics settings, the field, the ball, the referee and
// the robots (each from a robot file, with a team, a start pose and an
// optional player plugin). README.md ("World files") has the syntax:
//
//   world cycle=0.01 restitution=0.5 friction=0.2 seed=1
//   plugin_path "plugins"
//   field length=9 width=5
//   ball radius=0.11 mass=0.43 deceleration=0.4 x=0 y=0
//   referee goal_pause=1
//   robot blue1 file="robots/keeper.robot" team=blue x=-4.2 y=0 a=0 {
//     player goalkeeper policy=block
//   }
//
// A robot's block may also hold robot-file statements (shape, kicker,
// motion, sensor, mass): they add to its file, or define the robot alone.
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
bool load_world_file(const std::string& path, WorldSpec& out, std::string& error);

}  // namespace troupe::robocup
