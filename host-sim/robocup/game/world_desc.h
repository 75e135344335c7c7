// A RoboCup world as the one engine's world (host-sim/sim): the
// description Simulation runs on, and the scene the engine's cameras draw.
//   - a rigid world (WorldDesc::physics) with the world file's physics
//     settings, stepping every cycle_s;
//   - statics for the barrier, the goals in their colours (blue at -x,
//     yellow at +x, as F2000) and the corner posts, each the static rigid
//     body build_field() makes (its shapes, pose and user data), made before
//     any robot so the physics steps as RoboCup mode always did; in the grid
//     they are seen (rays, cameras) but leave collisions to the physics;
//   - robots: the ball first (robot 0, named "ball"), then every robot of
//     spec.robots in order, each an undriven rigid body (the game layer's
//     motion plugins and kicks set their velocities) with its exact shapes,
//     mass and inertia (a robot's kicker plates in their rest state);
//   - the green carpet with the field's white lines painted on the floor.
// Robots carry no Stage sensors and no controller.
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

/// The engine's description of `spec` (see above).
sim::WorldDesc world_desc(const WorldSpec& spec, const FieldColors& colors = {});

/// A robot's rigid shapes in kicker state `kicker_state` (robot frame): its
/// body's and, with a kicker, that state's plates.
std::vector<Shape> robot_shapes(const RobotSpec& spec, int kicker_state);

}  // namespace troupe::robocup
