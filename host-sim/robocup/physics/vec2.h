// Plane geometry for the RoboCup physics and its plugins: vectors, poses and
// the transforms between a body's frame and the world frame. Header-only, so
// plugins (separate shared libraries) use it without linking the simulator.
#pragma once

#include <cmath>

namespace troupe::robocup {

inline constexpr double kPi = 3.14159265358979323846;

/// A point or a vector in the plane: m (or m/s, N s, as the use says).
struct Vec2 {
  double x = 0, y = 0;

  constexpr Vec2 operator+(Vec2 o) const { return {x + o.x, y + o.y}; }
  constexpr Vec2 operator-(Vec2 o) const { return {x - o.x, y - o.y}; }
  constexpr Vec2 operator-() const { return {-x, -y}; }
  constexpr Vec2 operator*(double s) const { return {x * s, y * s}; }
  constexpr Vec2 operator/(double s) const { return {x / s, y / s}; }
  constexpr Vec2& operator+=(Vec2 o) { return *this = *this + o; }
  constexpr Vec2& operator-=(Vec2 o) { return *this = *this - o; }
  constexpr bool operator==(const Vec2&) const = default;
};

constexpr Vec2 operator*(double s, Vec2 v) {
  return v * s;
}
constexpr double dot(Vec2 a, Vec2 b) {
  return a.x * b.x + a.y * b.y;
}
/// The z component of the 3D cross product.
constexpr double cross(Vec2 a, Vec2 b) {
  return a.x * b.y - a.y * b.x;
}
/// w x r for an angular velocity w (rad/s) about z: the velocity of a point.
constexpr Vec2 cross(double w, Vec2 r) {
  return {-w * r.y, w * r.x};
}
/// The vector turned +90 degrees.
constexpr Vec2 perp(Vec2 v) {
  return {-v.y, v.x};
}
inline double length(Vec2 v) {
  return std::hypot(v.x, v.y);
}
constexpr double length_squared(Vec2 v) {
  return dot(v, v);
}
inline Vec2 normalized(Vec2 v) {
  double n = length(v);
  return n > 0 ? v / n : Vec2{1, 0};
}
inline Vec2 rotate(Vec2 v, double angle_rad) {
  double c = std::cos(angle_rad), s = std::sin(angle_rad);
  return {c * v.x - s * v.y, s * v.x + c * v.y};
}
/// The unit vector at `angle_rad` from the x axis.
inline Vec2 direction(double angle_rad) {
  return {std::cos(angle_rad), std::sin(angle_rad)};
}
/// An angle folded into [-pi, pi].
inline double wrap_angle(double a_rad) {
  return std::remainder(a_rad, 2 * kPi);
}

/// A frame in the plane: position (m) and heading (rad, counter-clockwise
/// from the world x axis).
struct Pose2 {
  double x = 0, y = 0, a = 0;

  constexpr Vec2 position() const { return {x, y}; }
  /// A point given in this frame, in the parent frame.
  Vec2 to_world(Vec2 local) const { return position() + rotate(local, a); }
  /// A point given in the parent frame, in this frame.
  Vec2 to_local(Vec2 world) const { return rotate(world - position(), -a); }
  /// A pose given in this frame, in the parent frame.
  Pose2 compose(Pose2 local) const {
    Vec2 p = to_world(local.position());
    return {p.x, p.y, wrap_angle(a + local.a)};
  }
  constexpr bool operator==(const Pose2&) const = default;
};

/// A rigid velocity: linear (m/s) and angular (rad/s), in the frame the
/// user says (world frame unless noted).
struct Twist {
  double vx = 0, vy = 0, w = 0;

  constexpr Vec2 linear() const { return {vx, vy}; }
  constexpr bool operator==(const Twist&) const = default;
};

}  // namespace troupe::robocup
