// A RoboCup world as the Stage engine's cameras see it: the one description
// RoboCup mode runs on (world_desc.h), to which a test or benchmark adds
// cameras on its robots (a Stage `camera` model's CameraDesc, omni or
// pinhole) before building a sim::World of it.
#pragma once

#include "host-sim/robocup/game/world_desc.h"

namespace troupe::robocup {

/// world_desc(spec, colors): the ball is robot 0, named "ball", the robots
/// of spec.robots follow in order.
inline sim::WorldDesc camera_scene(const WorldSpec& spec, const FieldColors& colors = {}) {
  return world_desc(spec, colors);
}

}  // namespace troupe::robocup
