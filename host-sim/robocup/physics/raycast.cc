#include "host-sim/robocup/physics/raycast.h"

#include <algorithm>

namespace troupe::robocup {
namespace {

// The ray against a unit circle at the origin (after scaling): the entry
// parameter, if the origin is outside.
bool unit_circle(Vec2 o, Vec2 d, double& t) {
  const double a = dot(d, d), b = dot(o, d), c = dot(o, o) - 1;
  if (c <= 0) return false;  // starts inside
  const double disc = b * b - a * c;
  if (disc < 0 || b >= 0) return false;
  t = (-b - std::sqrt(disc)) / a;
  return true;
}

}  // namespace

bool raycast(const PlacedShape& s, Vec2 origin, Vec2 dir, double max_range, RayShapeHit& hit) {
  switch (s.kind) {
    case ShapeKind::Circle: {
      double t;
      const double r = s.margin;
      if (!unit_circle((origin - s.center) / r, dir / r, t) || t > max_range) return false;
      hit.distance = t;
      hit.normal = normalized(origin + dir * t - s.center);
      return true;
    }
    case ShapeKind::Ellipse: {
      // In the ellipse's frame, scaled so that it becomes the unit circle;
      // the ray parameter is unchanged by the linear map.
      const Vec2 u = s.axis, v = perp(s.axis);
      const Vec2 rel = origin - s.center;
      const Vec2 o{dot(rel, u) / s.rx, dot(rel, v) / s.ry};
      const Vec2 d{dot(dir, u) / s.rx, dot(dir, v) / s.ry};
      double t;
      if (!unit_circle(o, d, t) || t > max_range) return false;
      const Vec2 p = o + d * t;  // on the unit circle; the normal maps by the inverse transpose
      hit.distance = t;
      hit.normal = normalized(u * (p.x / s.rx) + v * (p.y / s.ry));
      return true;
    }
    case ShapeKind::Polygon: {
      // Clip the ray's parameter interval by every edge's half-plane.
      double t_in = 0, t_out = max_range;
      int entry_edge = -1;
      for (int i = 0; i < s.vertex_count; ++i) {
        const Vec2 a = s.vertices[i], b = s.vertices[(i + 1) % s.vertex_count];
        const Vec2 n = -perp(normalized(b - a));  // outward
        const double num = dot(a - origin, n), den = dot(dir, n);
        if (den == 0) {
          if (num < 0) return false;  // parallel and outside this edge
          continue;
        }
        const double t = num / den;
        if (den < 0) {
          if (t > t_in) {
            t_in = t;
            entry_edge = i;
          }
        } else {
          t_out = std::min(t_out, t);
        }
        if (t_in > t_out) return false;
      }
      if (entry_edge < 0) return false;  // starts inside
      hit.distance = t_in;
      const Vec2 a = s.vertices[entry_edge], b = s.vertices[(entry_edge + 1) % s.vertex_count];
      hit.normal = -perp(normalized(b - a));
      return true;
    }
  }
  return false;
}

}  // namespace troupe::robocup
