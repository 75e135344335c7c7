// A ball as the engine's body: a round puck with its own rigid body that
// rolls to rest. The one conversion for a Stage world's `ball` model and a
// RoboCup match's ball.
#pragma once

#include "host-sim/sim/desc.h"

namespace troupe::sim {

/// The engine's robot for `ball` (robots and pucks share RobotDesc): a puck
/// (no drive; pushed, kicked, carried by grippers) whose rigid body is a
/// solid sphere of the ball's radius and mass, undriven, slowed by its
/// deceleration; its outline a polygon of the circle.
RobotDesc ball_robot(const BallDesc& ball);

}  // namespace troupe::sim
