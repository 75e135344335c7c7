// The few intersection tests the engine's step needs, over the project's
// plane geometry (wire/geometry.h). Everything in metres and radians.
#pragma once

#include <cmath>
#include <span>

#include "wire/geometry.h"

namespace troupe::sim {

using geometry::kPi;
using geometry::Vec2;
/// The engine's pose: the project's Pose2 (also used for velocities).
using Pose = geometry::Pose2;
using geometry::compose;
using geometry::cross;
using geometry::dot;
using geometry::length;
using geometry::length_squared;
using geometry::relative;
using geometry::transform;
using geometry::wrap_angle;

/// Distance along the ray `origin + t * dir` (|dir| = 1) to the first crossing
/// of segment [a, b], or a negative value when they do not meet.
double ray_segment(Vec2 origin, Vec2 dir, Vec2 a, Vec2 b);

/// Nearest crossing of the ray with a closed polygon's edges, or negative.
double ray_polygon(Vec2 origin, Vec2 dir, std::span<const Vec2> polygon);
/// The same, for the many rays from one origin: `rel` holds each vertex of
/// the polygon less the origin (m), computed once for them all.
double ray_polygon(Vec2 origin, Vec2 dir, std::span<const Vec2> polygon, const Vec2* rel);

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
