// From a Stage world file to a WorldDesc: the model type table, units
// converted once, bitmaps loaded, sensors and bodies flattened onto robots.
//
// Model types (the world file's keywords; `define` builds on these):
//   model       a static obstacle (blocks, or a bitmap with `boundary`)
//   position    a robot: drive "diff"|"omni"|"car", velocity/acceleration
//               bounds, localization "gps"|"odom", odom_error, ctrl
//   ranger      sonar/IR/laser: `sensor( pose range fov samples noise )`
//               children, or Stage 3's scount/spose[i]/sview
//   laser       Stage 3's laser (range_min range_max fov samples)
//   blobfinder  colors_count colors [..] image [w h] range fov pan
//   fiducial    range_min range_max range_max_id fov fiducial_key
//   bumper      bcount bpose[i] [x y a] blength
//   block       points N point[i] [x y] z [..]: a polygon of its model
//   window      kept for the viewer
// camera, gripper, actuator, ... load as plain models with a warning.
#pragma once

#include <string>

#include "host-sim/sim/desc.h"
#include "host-sim/world/diagnostics.h"
#include "host-sim/world/worldfile.h"

namespace troupe::sim {

/// Top-level models another layer reads: a RoboCup match's field, referee,
/// ball and robots go to the game layer (host-sim/robocup/game/
/// world_load.h, the one loader entry). The loader offers it every
/// top-level model in file order and reads only those it does not take;
/// at the end, before reporting unused keys, the handoff reads what it
/// took (and the world's properties it needs), reporting to `diags`.
class ModelHandoff {
 public:
  virtual ~ModelHandoff() = default;
  /// True when the handoff takes `model` (it is then its to read).
  virtual bool take(const world::Entity& model) = 0;
  virtual void finish(const world::WorldFile& file, world::Diagnostics& diags) = 0;
};

/// Converts a parsed world file. Warnings (unknown keys, types Troupe does
/// not simulate) and errors (wrong value kinds, missing bitmaps, a grid too
/// large) go to `diags` with file:line. False when there were errors.
bool load_world(const world::WorldFile& file, WorldDesc& out, world::Diagnostics& diags);
/// The same, handing the models `handoff` takes over to it (null: none).
bool load_world(const world::WorldFile& file, WorldDesc& out, world::Diagnostics& diags,
                ModelHandoff* handoff);

/// True for the Stage sensor models a robot carries (ranger, laser,
/// blobfinder, fiducial, bumper, camera, gripper): what load_robot_sensors()
/// reads.
bool is_robot_sensor(const std::string& type);

/// Reads the Stage sensor models among `model`'s children into out's
/// sensor lists, in the model's frame, as the loader reads a position
/// model's: a model of another kind that carries Stage's sensors (a RoboCup
/// robot) reuses it. Other children, and the sensors' bodies, are left
/// alone. A camera stands on `out.look.height` (m), the model's height.
/// False when there were errors (in `diags`, file:line).
bool load_robot_sensors(const world::WorldFile& file, const world::Entity& model, RobotDesc& out,
                        world::Diagnostics& diags);

/// Reads a `ball` model's keys into `out` (sim/desc.h, BallDesc), as the
/// loader reads a Stage world's ball: a RoboCup match's ball (read by the
/// game layer's reader) reuses it. Unknown keys are left for the file's
/// warn_unused. False when there were errors (in `diags`, file:line).
bool load_ball(const world::WorldFile& file, const world::Entity& model, BallDesc& out,
               world::Diagnostics& diags);

/// Reads, parses and converts a world file.
bool load_world_file(const std::string& path, WorldDesc& out, world::Diagnostics& diags);

}  // namespace troupe::sim
