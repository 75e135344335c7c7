// A RoboCup world as the Stage engine's cameras see it (host-sim/sim,
// camera.cc): the green carpet with its white lines painted on the floor,
// the goals in their colours (blue at -x, yellow at +x, as F2000), the
// barrier and corner posts, the orange ball and the robots at their
// kick-off poses. The RoboCup simulation itself has no image renderer; this
// scene lets the one renderer draw a match's field, for cameras put on its
// robots (a Stage `camera` model's CameraDesc, omni or pinhole).
#pragma once

#include <cstdint>

#include "host-sim/robocup/game/world_spec.h"
#include "host-sim/sim/desc.h"

namespace troupe::robocup {

/// Colours of the field, 0x00RRGGBB.
struct FieldColors {
  uint32_t carpet = 0x1E8C28, lines = 0xFFFFFF;
  uint32_t blue_goal = 0x1E3CFF, yellow_goal = 0xFFE01E;
  uint32_t barrier = 0xF0F0F0, ball = 0xFF8000, robot = 0x181818;
};

/// The scene of `spec`: statics for the barrier, goals and corner posts
/// (their heights from the field), robots for the ball and every robot (in
/// the order of spec.robots, after the ball, which is robot 0, named
/// "ball"), the floor painted with the field's lines. Robots carry no
/// sensors and no controller; add cameras to them before building a World.
sim::WorldDesc camera_scene(const WorldSpec& spec, const FieldColors& colors = {});

}  // namespace troupe::robocup
