// RoboCup landmark codes: how a fiducial detection's `id` says what was
// seen. A simulator in RoboCup mode (host-sim/robocup) sends
// code = kind * 100 + id, where id is the object's number within its kind
// (a negative id, the centre circle, becomes 99). Clients decode it to find
// the ball or a goal whichever sensor saw it.
#pragma once

#include <cstdint>

namespace troupe::wire {

enum class LandmarkKind : uint8_t {
  /// id 0
  Ball = 0,
  /// id 0: the blue goal (at -x), 1: the yellow goal (at +x); the mouth's centre
  Goal = 1,
  /// id 0/1: the blue goal's right/left post seen from the field, 2/3: yellow's
  GoalPost = 2,
  /// id 0..3 counter-clockwise from the (+x, +y) corner
  CornerPost = 3,
  /// id: the field line's index; 99: the centre circle
  Line = 4,
  /// id: the robot's number (0..98)
  Robot = 5,
};

inline constexpr int32_t kLandmarkStride = 100;
/// What a negative object id (the centre circle) is sent as.
inline constexpr int32_t kLandmarkNoId = 99;

inline constexpr int32_t landmark_code(LandmarkKind kind, int id) {
  return int32_t(kind) * kLandmarkStride + (id >= 0 && id < kLandmarkNoId ? id : kLandmarkNoId);
}
/// The kind of a code; codes outside every kind give false.
inline constexpr bool landmark_kind(int32_t code, LandmarkKind& out) {
  if (code < 0 || code / kLandmarkStride > int32_t(LandmarkKind::Robot)) return false;
  out = LandmarkKind(code / kLandmarkStride);
  return true;
}
/// The object's number within its kind (-1 for kLandmarkNoId).
inline constexpr int landmark_id(int32_t code) {
  const int id = code % kLandmarkStride;
  return id == kLandmarkNoId ? -1 : id;
}

}  // namespace troupe::wire
