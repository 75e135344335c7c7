// The primitives bodies are built from: circles, ellipses and convex
// polygons (rectangles and triangles are polygons), each with a height
// range. All are convex, so collision uses their support functions.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "host-sim/robocup/physics/vec2.h"

namespace troupe::robocup {

enum class ShapeKind : uint8_t { Circle, Ellipse, Polygon };

inline constexpr int kMaxPolygonVertices = 8;
/// The top of a shape that reaches any height, m.
inline constexpr double kUnboundedZ = std::numeric_limits<double>::infinity();

/// A convex primitive in its body's frame. Build one with make_circle(),
/// make_ellipse(), make_rect() or make_polygon().
struct Shape {
  ShapeKind kind = ShapeKind::Circle;
  /// Circle and ellipse centre, body frame, m.
  Vec2 center;
  /// Circle radius, m.
  double radius = 0;
  /// Ellipse semi-axes along its own x and y, m, and its own x axis's angle
  /// in the body frame, rad.
  double rx = 0, ry = 0, angle = 0;
  /// Polygon corners, body frame, m, counter-clockwise.
  int vertex_count = 0;
  Vec2 vertices[kMaxPolygonVertices];
  /// Height range above the floor, m. Two shapes whose ranges do not
  /// overlap pass over/under each other.
  double z_min = 0, z_max = kUnboundedZ;
  /// The user's label (e.g. "kicker plate"); the physics ignores it.
  uint32_t tag = 0;
};

Shape make_circle(Vec2 center, double radius);
/// `angle_rad`: the ellipse's x semi-axis direction in the body frame.
Shape make_ellipse(Vec2 center, double rx, double ry, double angle_rad = 0);
/// A rectangle `length` (along x before turning) by `width`, m.
Shape make_rect(Vec2 center, double length, double width, double angle_rad = 0);
/// A convex polygon of 3..8 corners in either winding. False with `error`
/// when it is not convex, too small or has too many corners.
bool make_polygon(std::span<const Vec2> points, Shape& out, std::string& error);
/// Checks a shape's sizes (positive radii, sane polygon); false with `error`.
bool validate(const Shape& shape, std::string& error);
/// The same shape limited to heights [z_min, z_max], m.
Shape with_height(Shape shape, double z_min, double z_max);
/// True when the two height ranges overlap (touching counts).
inline bool heights_overlap(const Shape& a, const Shape& b) {
  return a.z_min <= b.z_max && b.z_min <= a.z_max;
}

/// Area (m^2), centroid (body frame, m) and second moment of area about the
/// body origin (m^4): mass properties at unit density.
struct AreaProperties {
  double area = 0;
  Vec2 centroid;
  double second_moment = 0;
};
AreaProperties area_properties(const Shape& shape);

/// The shape's outline in its body's frame, m: a polygon's corners, or
/// `round_sides` points around a circle or ellipse (for grids, rays and
/// cameras, which need polygons). The default: the grid's cells are coarser
/// than the difference on field-sized posts and balls.
inline constexpr int kRoundOutlineSides = 24;
std::vector<Vec2> outline(const Shape& shape, int round_sides = kRoundOutlineSides);

/// The farthest distance of the shape from `point` (body frame), m.
double reach_from(const Shape& shape, Vec2 point);

/// A shape placed in the world: what the collision routines work on.
/// Circles are a point core plus a margin (their radius), which keeps the
/// distance computation exact for them.
struct PlacedShape {
  ShapeKind kind = ShapeKind::Circle;
  Vec2 center;                         // circle/ellipse centre, world, m
  double margin = 0;                   // circle radius, m
  double rx = 0, ry = 0;               // ellipse semi-axes, m
  Vec2 axis{1, 0};                     // ellipse x axis, world, unit
  int vertex_count = 0;                // polygon
  Vec2 vertices[kMaxPolygonVertices];  // world, m, counter-clockwise
  double z_min = 0, z_max = kUnboundedZ;
};

PlacedShape place(const Shape& shape, const Pose2& body_pose);
/// The core's farthest point along `d` (world). For polygons `vertex` is the
/// corner's index, otherwise -1.
Vec2 support(const PlacedShape& s, Vec2 d, int* vertex = nullptr);

/// An axis-aligned box, world, m.
struct Aabb {
  Vec2 lo, hi;
  bool overlaps(const Aabb& o) const {
    return lo.x <= o.hi.x && o.lo.x <= hi.x && lo.y <= o.hi.y && o.lo.y <= hi.y;
  }
};
Aabb bounds(const PlacedShape& s);

}  // namespace troupe::robocup
