// A kicker's push on a ball, one rule for every kicker: a RoboCup robot's
// (the game layer's kicker states) and a Stage robot's `kicker` model (the
// engine's, sim/kicker.h).
#pragma once

#include <span>

#include "host-sim/robocup/physics/world.h"

namespace troupe::robocup {

/// When one of `plates` (shapes in the frame of body `kicker`) whose height
/// range overlaps the ball's lies within `reach` m of body `ball`'s first
/// shape, the ball gains `speed` m/s along the kicker's heading turned by
/// `direction_rad` (its frame), and the kicker takes the opposite impulse
/// (the plate pushes against its robot). True when it kicked.
bool kick_ball(World& w, BodyId kicker, std::span<const Shape> plates, double reach, double direction_rad,
               double speed, BodyId ball);

}  // namespace troupe::robocup
