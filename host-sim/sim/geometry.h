// Plane geometry for the engine: points, poses, and the few intersection
// tests the step needs. Everything in metres and radians.
#pragma once

#include <cmath>
#include <span>

namespace troupe::sim {

inline constexpr double kPi = 3.14159265358979323846;

struct Vec2 {
  double x = 0;  // m
  double y = 0;  // m
};

inline Vec2 operator+(Vec2 a, Vec2 b) {
  return {a.x + b.x, a.y + b.y};
}
inline Vec2 operator-(Vec2 a, Vec2 b) {
  return {a.x - b.x, a.y - b.y};
}
inline Vec2 operator*(double s, Vec2 a) {
  return {s * a.x, s * a.y};
}
inline double dot(Vec2 a, Vec2 b) {
  return a.x * b.x + a.y * b.y;
}
inline double cross(Vec2 a, Vec2 b) {
  return a.x * b.y - a.y * b.x;
}
inline double length(Vec2 a) {
  return std::hypot(a.x, a.y);
}

/// A pose in the plane: position (m) and heading (rad, counter-clockwise
/// from the x axis). Also used for velocities (m/s, m/s, rad/s).
struct Pose {
  double x = 0;
  double y = 0;
  double a = 0;
};

/// Angle wrapped into [-pi, pi], rad.
inline double wrap_angle(double a) {
  return std::remainder(a, 2 * kPi);
}

/// `local` (a pose in `frame`'s coordinates) in the frame `frame` lives in.
inline Pose compose(const Pose& frame, const Pose& local) {
  double c = std::cos(frame.a), s = std::sin(frame.a);
  return {frame.x + c * local.x - s * local.y, frame.y + s * local.x + c * local.y,
          wrap_angle(frame.a + local.a)};
}

/// `global` expressed in `frame`'s coordinates (the inverse of compose).
inline Pose relative(const Pose& frame, const Pose& global) {
  double c = std::cos(frame.a), s = std::sin(frame.a);
  double dx = global.x - frame.x, dy = global.y - frame.y;
  return {c * dx + s * dy, -s * dx + c * dy, wrap_angle(global.a - frame.a)};
}

/// A point of `frame`'s coordinates in the outer frame.
inline Vec2 transform(const Pose& frame, Vec2 p) {
  double c = std::cos(frame.a), s = std::sin(frame.a);
  return {frame.x + c * p.x - s * p.y, frame.y + s * p.x + c * p.y};
}

/// Distance along the ray `origin + t * dir` (|dir| = 1) to the first crossing
/// of segment [a, b], or a negative value when they do not meet.
double ray_segment(Vec2 origin, Vec2 dir, Vec2 a, Vec2 b);

/// Nearest crossing of the ray with a closed polygon's edges, or negative.
double ray_polygon(Vec2 origin, Vec2 dir, std::span<const Vec2> polygon);

/// True when the point is inside the closed polygon (even-odd rule).
bool point_in_polygon(Vec2 p, std::span<const Vec2> polygon);

/// True when segments [a, b] and [c, d] touch or cross.
bool segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d);

/// True when two closed polygons overlap (an edge crossing or one inside the
/// other). Both in the same frame.
bool polygons_overlap(std::span<const Vec2> p, std::span<const Vec2> q);

/// True when a closed polygon overlaps the axis-aligned box [lo, hi].
bool polygon_overlaps_box(std::span<const Vec2> polygon, Vec2 lo, Vec2 hi);

/// True when segment [a, b] touches the axis-aligned box [lo, hi].
bool segment_overlaps_box(Vec2 a, Vec2 b, Vec2 lo, Vec2 hi);

}  // namespace troupe::sim
