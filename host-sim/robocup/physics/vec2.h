// Plane geometry for the RoboCup physics and its plugins: the project's one
// geometry (wire/geometry.h), header-only, so plugins (separate shared
// libraries) use it without linking the simulator.
#pragma once

#include "wire/geometry.h"

namespace troupe::robocup {

using geometry::cross;
using geometry::direction;
using geometry::dot;
using geometry::kPi;
using geometry::length;
using geometry::length_squared;
using geometry::normalized;
using geometry::perp;
using geometry::Pose2;
using geometry::rotate;
using geometry::Twist;
using geometry::Vec2;
using geometry::wrap_angle;

}  // namespace troupe::robocup
