// What a RoboCup detection is on the wire: a fiducial kind and an id within
// that kind (wire/schemas/fiducial.fbs), so clients never decode an id.
//   Ball  0
//   Goal  0 the blue goal (-x), 1 the yellow goal (+x)
//   Post  0/1 the blue goal's right/left post seen from the field, 2/3
//         yellow's; 4..7 the corner posts counter-clockwise from (+x, +y)
//   Line  the index into FieldGeometry::lines; kCentreCircleId the circle
//   Robot the robot's index
// Header-only (the generated schema header is header-only too), so the
// landmark learner plugin writes the same keys the server sends.
#pragma once

#include <cstdint>
#include <optional>

#include "host-sim/robocup/api/world_view.h"
#include "wire/fiducial_key.h"

namespace troupe::robocup {

using wire::FiducialKey;

/// The centre circle's Line id (the straight lines are numbered from 0).
inline constexpr int32_t kCentreCircleId = 99;
/// Corner posts follow the four goal posts.
inline constexpr int32_t kFirstCornerPostId = 4;

/// The key of a detected object; nothing for walls and barriers, which are
/// no landmarks a client can use.
inline std::optional<FiducialKey> fiducial_key(ObjectKind kind, int id) {
  using K = wire::FiducialKind;
  switch (kind) {
    case ObjectKind::Ball:
      return FiducialKey{K::Ball, 0};
    case ObjectKind::Goal:
      return FiducialKey{K::Goal, id};
    case ObjectKind::GoalPost:
      return FiducialKey{K::Post, id};
    case ObjectKind::CornerPost:
      return FiducialKey{K::Post, kFirstCornerPostId + id};
    case ObjectKind::Line:
      return FiducialKey{K::Line, id < 0 ? kCentreCircleId : id};
    case ObjectKind::Robot:
      return FiducialKey{K::Robot, id};
    case ObjectKind::Structure:
      break;
  }
  return std::nullopt;
}

}  // namespace troupe::robocup
