// Planar poses and the few operations every desktop algorithm needs on them.
// Doubles: the filters accumulate thousands of small increments, and the wire
// format's float32 is converted once at the edge.
#pragma once

#include <cmath>

namespace troupe::desktop {

inline constexpr double kPi = 3.14159265358979323846;

/// An angle brought into [-pi, pi), rad.
inline double wrap_angle(double a_rad) {
  a_rad = std::fmod(a_rad + kPi, 2 * kPi);
  return a_rad < 0 ? a_rad + kPi : a_rad - kPi;
}

/// A pose in the plane (or a motion increment in the frame of the pose it
/// starts from): m, m, rad.
struct Pose2 {
  double x = 0, y = 0, a = 0;
};

/// `b` expressed in the frame of `a`, brought back into a's parent frame
/// (a ⊕ b): where you end up after moving by `b` from `a`.
inline Pose2 compose(const Pose2& a, const Pose2& b) {
  double c = std::cos(a.a), s = std::sin(a.a);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, wrap_angle(a.a + b.a)};
}

/// The motion from `a` to `b` in a's frame (a⁻¹ ⊕ b).
inline Pose2 between(const Pose2& a, const Pose2& b) {
  double c = std::cos(a.a), s = std::sin(a.a);
  double dx = b.x - a.x, dy = b.y - a.y;
  return {c * dx + s * dy, -s * dx + c * dy, wrap_angle(b.a - a.a)};
}

/// Linear interpolation of position and shortest-arc interpolation of the
/// heading; `f` = 0 gives `a`, 1 gives `b`.
inline Pose2 interpolate(const Pose2& a, const Pose2& b, double f) {
  return {a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), wrap_angle(a.a + f * wrap_angle(b.a - a.a))};
}

/// Translational distance between two poses, m.
inline double distance(const Pose2& a, const Pose2& b) {
  return std::hypot(b.x - a.x, b.y - a.y);
}

}  // namespace troupe::desktop
