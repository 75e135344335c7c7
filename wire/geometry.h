// The project's one plane geometry: vectors, poses, rigid velocities, the
// angle wrap and the transforms between a frame and its parent. Header-only
// and free of any other Troupe header, so every layer (the client, drivers,
// the simulator, RoboCup plugins built as separate libraries) uses the same
// arithmetic: a pose composed in a driver and in the simulator gives the
// same bits. Metres and radians throughout; angles counter-clockwise.
#pragma once

#include <cmath>

namespace troupe::geometry {

inline constexpr double kPi = 3.14159265358979323846;

/// An angle folded into [-pi, pi], rad. std::remainder is exact, so a
/// wrapped angle carries no rounding error of its own.
inline double wrap_angle(double a_rad) {
  return std::remainder(a_rad, 2 * kPi);
}

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
  return {s * v.x, s * v.y};
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
/// The unit vector along `v`; +x for the zero vector.
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

struct Pose2;
Vec2 transform(const Pose2& frame, Vec2 p);
Pose2 compose(const Pose2& frame, const Pose2& local);
Pose2 relative(const Pose2& frame, const Pose2& global);

/// A frame in the plane: position (m) and heading (rad). Also a motion
/// increment in the frame it starts from, and, where a use says so, a
/// velocity (m/s, m/s, rad/s).
struct Pose2 {
  double x = 0, y = 0, a = 0;

  constexpr Vec2 position() const { return {x, y}; }
  /// A point given in this frame, in the parent frame.
  Vec2 to_world(Vec2 local) const { return transform(*this, local); }
  /// A point given in the parent frame, in this frame.
  Vec2 to_local(Vec2 world) const {
    Pose2 r = relative(*this, {world.x, world.y, a});
    return {r.x, r.y};
  }
  /// A pose given in this frame, in the parent frame.
  Pose2 compose(const Pose2& local) const { return geometry::compose(*this, local); }
  constexpr bool operator==(const Pose2&) const = default;
};

/// A point of `frame`'s coordinates in the frame `frame` lives in.
inline Vec2 transform(const Pose2& frame, Vec2 p) {
  double c = std::cos(frame.a), s = std::sin(frame.a);
  return {frame.x + c * p.x - s * p.y, frame.y + s * p.x + c * p.y};
}

/// `local` (a pose in `frame`'s coordinates) in the frame `frame` lives in
/// (frame ⊕ local): where one ends after moving by `local` from `frame`.
inline Pose2 compose(const Pose2& frame, const Pose2& local) {
  Vec2 p = transform(frame, {local.x, local.y});
  return {p.x, p.y, wrap_angle(frame.a + local.a)};
}

/// `global` expressed in `frame`'s coordinates (frame⁻¹ ⊕ global), the
/// inverse of compose: the motion from `frame` to `global`.
inline Pose2 relative(const Pose2& frame, const Pose2& global) {
  double c = std::cos(frame.a), s = std::sin(frame.a);
  double dx = global.x - frame.x, dy = global.y - frame.y;
  return {c * dx + s * dy, -s * dx + c * dy, wrap_angle(global.a - frame.a)};
}

/// Linear interpolation of the position and shortest-arc interpolation of
/// the heading; `f` = 0 gives `a`, 1 gives `b`.
inline Pose2 interpolate(const Pose2& a, const Pose2& b, double f) {
  return {a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), wrap_angle(a.a + f * wrap_angle(b.a - a.a))};
}

/// Distance between two poses' positions, m.
inline double distance(const Pose2& a, const Pose2& b) {
  return std::hypot(b.x - a.x, b.y - a.y);
}

/// A rigid velocity: linear (m/s) and angular (rad/s), in the frame the
/// user says (world frame unless noted).
struct Twist {
  double vx = 0, vy = 0, w = 0;

  constexpr Vec2 linear() const { return {vx, vy}; }
  constexpr bool operator==(const Twist&) const = default;
};

}  // namespace troupe::geometry
