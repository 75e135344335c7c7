// Planar poses for the desktop algorithms: the project's one geometry
// (wire/geometry.h). Doubles: the filters accumulate thousands of small
// increments, and the wire format's float32 is converted once at the edge.
#pragma once

#include "wire/geometry.h"

namespace troupe::desktop {

using geometry::compose;
using geometry::distance;
using geometry::interpolate;
using geometry::kPi;
using geometry::Pose2;
using geometry::relative;
using geometry::wrap_angle;

}  // namespace troupe::desktop
