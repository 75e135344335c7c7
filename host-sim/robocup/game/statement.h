// What the RoboCup readers (field, ball, referee, robots, console) read: a
// statement, `keyword [word ...] [key=value ...]` with child statements, and
// where it was written. World and robot files are Stage world files
// (host-sim/world): `from_stage` turns a parsed one into statements, so a
// RoboCup match is one more Stage world. `parse_commands` reads the
// console's one-line commands (`start blue0 goalkeeper policy=block`).
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "host-sim/robocup/api/options.h"
#include "host-sim/sim/desc.h"
#include "host-sim/world/worldfile.h"

namespace troupe::robocup {

struct Statement {
  std::string keyword;
  /// Words after the keyword that are not key=value.
  std::vector<std::string> args;
  /// key=value pairs in the order written.
  std::vector<std::pair<std::string, std::string>> options;
  std::vector<Statement> children;
  /// A `robot`'s Stage sensor models (ranger, laser, camera, fiducial,
  /// blobfinder, bumper, gripper), read by the engine's loader: only the
  /// sensor lists are filled, cameras standing on height 0. Null for none.
  std::shared_ptr<const sim::RobotDesc> stage_sensors;
  /// A `ball`'s keys, read by the engine's loader (sim::load_ball): the
  /// one reader of `ball`, in a match as in a Stage world.
  std::shared_ptr<const sim::BallDesc> ball;
  std::string file;
  int line = 0;

  /// "file:line".
  std::string where() const { return file + ":" + std::to_string(line); }
  /// The options as an Options object (for typed reading).
  Options reader() const;
};

/// The RoboCup statements of a Stage world (README.md, "World files"):
/// the world's properties become a `world` statement (`interval_sim` in ms
/// as `cycle` in s) and `plugin_path`; `robocup_field`, `ball`, `referee`
/// and every model of type `robocup_robot` (or a type defined from it)
/// become `field`, `ball`, `referee` and `robot NAME` (its `pose [x y z a]`,
/// a in degrees unless the world says `unit_angle "radians"`, as x, y, a in
/// rad). In a robot, `shape ( kind "rect" ... )`, `kicker ( state ( name
/// "rest" ... ) )`, `motion_plugin ( plugin "diff_drive" ... )`,
/// `sensor_plugin ( plugin "laser" ... )`, `player ( plugin "striker" ... )`,
/// `mass` and `inertia`, and the Stage engine's sensor models (`ranger`,
/// `camera`, `fiducial`, `blobfinder`, ...: Statement::stage_sensors). A tuple `[0 0.6]` becomes the list
/// `0,0.6`. False with "file:line: why" for a model no RoboCup world has.
bool from_stage(const world::WorldFile& file, std::vector<Statement>& out, std::string& error);
/// The same for the world's properties and just `models`, top-level models
/// of `file` (the one loader, world_load.h, hands over a match's models).
bool from_stage(const world::WorldFile& file, std::span<const world::Entity* const> models,
                std::vector<Statement>& out, std::string& error);

/// Reads and parses a Stage world file for RoboCup (errors and warnings of
/// the Stage parser with file:line in `error`).
bool load_stage_file(const std::string& path, std::vector<Statement>& out, std::string& error);
/// The same for text, named `file` (includes resolve next to it).
bool parse_stage_text(const std::string& text, const std::string& file, std::vector<Statement>& out,
                      std::string& error);

/// Console commands: one per line (or `;`), `keyword word ... key=value`,
/// `#` comments, "quotes" around spaces. False with "name:line: why".
/// `first_line` numbers text's first line (a console reading one line at
/// a time says which).
bool parse_commands(const std::string& text, const std::string& name, std::vector<Statement>& out,
                    std::string& error, int first_line = 1);

/// The folder part of a path ("" for a bare file name).
std::string folder_of(const std::string& path);

}  // namespace troupe::robocup
