#include "host-sim/robocup/physics/shape.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace troupe::robocup {

Shape make_circle(Vec2 center, double radius) {
  Shape s;
  s.kind = ShapeKind::Circle;
  s.center = center;
  s.radius = radius;
  return s;
}

Shape make_ellipse(Vec2 center, double rx, double ry, double angle_rad) {
  Shape s;
  s.kind = ShapeKind::Ellipse;
  s.center = center;
  s.rx = rx;
  s.ry = ry;
  s.angle = angle_rad;
  return s;
}

Shape make_rect(Vec2 center, double length, double width, double angle_rad) {
  Shape s;
  s.kind = ShapeKind::Polygon;
  s.vertex_count = 4;
  const Vec2 corners[4] = {
      {-length / 2, -width / 2}, {length / 2, -width / 2}, {length / 2, width / 2}, {-length / 2, width / 2}};
  for (int i = 0; i < 4; ++i) s.vertices[i] = center + rotate(corners[i], angle_rad);
  return s;
}

namespace {

double signed_area(const Vec2* v, int n) {
  double a = 0;
  for (int i = 0; i < n; ++i) a += cross(v[i], v[(i + 1) % n]);
  return a / 2;
}

}  // namespace

bool make_polygon(std::span<const Vec2> points, Shape& out, std::string& error) {
  if (points.size() < 3 || points.size() > size_t(kMaxPolygonVertices)) {
    error = "a polygon needs 3 to " + std::to_string(kMaxPolygonVertices) + " corners, got " +
            std::to_string(points.size());
    return false;
  }
  Shape s;
  s.kind = ShapeKind::Polygon;
  s.vertex_count = int(points.size());
  std::copy(points.begin(), points.end(), s.vertices);
  if (signed_area(s.vertices, s.vertex_count) < 0) std::reverse(s.vertices, s.vertices + s.vertex_count);
  if (!validate(s, error)) return false;
  out = s;
  return true;
}

bool validate(const Shape& s, std::string& error) {
  char buf[128];
  switch (s.kind) {
    case ShapeKind::Circle:
      if (!(s.radius > 0) || !std::isfinite(s.radius)) {
        snprintf(buf, sizeof buf, "circle radius must be > 0 m, got %g", s.radius);
        error = buf;
        return false;
      }
      break;
    case ShapeKind::Ellipse:
      if (!(s.rx > 0) || !(s.ry > 0) || !std::isfinite(s.rx) || !std::isfinite(s.ry)) {
        snprintf(buf, sizeof buf, "ellipse semi-axes must be > 0 m, got %g and %g", s.rx, s.ry);
        error = buf;
        return false;
      }
      break;
    case ShapeKind::Polygon: {
      const int n = s.vertex_count;
      if (n < 3 || n > kMaxPolygonVertices) {
        error = "a polygon needs 3 to 8 corners";
        return false;
      }
      // Counter-clockwise and strictly convex: every turn is to the left.
      for (int i = 0; i < n; ++i) {
        Vec2 e0 = s.vertices[(i + 1) % n] - s.vertices[i];
        Vec2 e1 = s.vertices[(i + 2) % n] - s.vertices[(i + 1) % n];
        if (!(cross(e0, e1) > 1e-12)) {
          snprintf(buf, sizeof buf, "polygon is not strictly convex at corner %d", (i + 1) % n);
          error = buf;
          return false;
        }
      }
      if (signed_area(s.vertices, n) < 1e-8) {
        error = "polygon area is below 1e-8 m^2";
        return false;
      }
      break;
    }
  }
  if (!(s.z_min <= s.z_max)) {
    snprintf(buf, sizeof buf, "height range [%g, %g] m is empty", s.z_min, s.z_max);
    error = buf;
    return false;
  }
  return true;
}

Shape with_height(Shape shape, double z_min, double z_max) {
  shape.z_min = z_min;
  shape.z_max = z_max;
  return shape;
}

AreaProperties area_properties(const Shape& s) {
  AreaProperties p;
  switch (s.kind) {
    case ShapeKind::Circle:
      p.area = kPi * s.radius * s.radius;
      p.centroid = s.center;
      p.second_moment = p.area * (s.radius * s.radius / 2 + length_squared(s.center));
      break;
    case ShapeKind::Ellipse:
      p.area = kPi * s.rx * s.ry;
      p.centroid = s.center;
      p.second_moment = p.area * ((s.rx * s.rx + s.ry * s.ry) / 4 + length_squared(s.center));
      break;
    case ShapeKind::Polygon: {
      Vec2 c;
      double j = 0;
      for (int i = 0; i < s.vertex_count; ++i) {
        Vec2 a = s.vertices[i], b = s.vertices[(i + 1) % s.vertex_count];
        double k = cross(a, b);
        p.area += k / 2;
        c += (a + b) * k;
        j += k * (dot(a, a) + dot(a, b) + dot(b, b));
      }
      p.centroid = c / (6 * p.area);
      p.second_moment = j / 12;
      break;
    }
  }
  return p;
}

double reach_from(const Shape& s, Vec2 point) {
  switch (s.kind) {
    case ShapeKind::Circle:
      return length(s.center - point) + s.radius;
    case ShapeKind::Ellipse:
      return length(s.center - point) + std::max(s.rx, s.ry);
    case ShapeKind::Polygon: {
      double r = 0;
      for (int i = 0; i < s.vertex_count; ++i) r = std::max(r, length(s.vertices[i] - point));
      return r;
    }
  }
  return 0;
}

PlacedShape place(const Shape& s, const Pose2& pose) {
  PlacedShape p;
  p.kind = s.kind;
  p.z_min = s.z_min;
  p.z_max = s.z_max;
  switch (s.kind) {
    case ShapeKind::Circle:
      p.center = pose.to_world(s.center);
      p.margin = s.radius;
      break;
    case ShapeKind::Ellipse:
      p.center = pose.to_world(s.center);
      p.rx = s.rx;
      p.ry = s.ry;
      p.axis = direction(pose.a + s.angle);
      break;
    case ShapeKind::Polygon:
      p.vertex_count = s.vertex_count;
      for (int i = 0; i < s.vertex_count; ++i) p.vertices[i] = pose.to_world(s.vertices[i]);
      p.center = pose.to_world(area_properties(s).centroid);
      break;
  }
  return p;
}

Vec2 support(const PlacedShape& s, Vec2 d, int* vertex) {
  if (vertex) *vertex = -1;
  switch (s.kind) {
    case ShapeKind::Circle:
      return s.center;
    case ShapeKind::Ellipse: {
      Vec2 v = perp(s.axis);
      double du = dot(d, s.axis) * s.rx, dv = dot(d, v) * s.ry;
      double n = std::hypot(du, dv);
      if (n == 0) return s.center + s.axis * s.rx;
      return s.center + s.axis * (s.rx * du / n) + v * (s.ry * dv / n);
    }
    case ShapeKind::Polygon: {
      int best = 0;
      double best_dot = dot(s.vertices[0], d);
      for (int i = 1; i < s.vertex_count; ++i) {
        double k = dot(s.vertices[i], d);
        if (k > best_dot) {
          best_dot = k;
          best = i;
        }
      }
      if (vertex) *vertex = best;
      return s.vertices[best];
    }
  }
  return s.center;
}

Aabb bounds(const PlacedShape& s) {
  switch (s.kind) {
    case ShapeKind::Circle:
      return {s.center - Vec2{s.margin, s.margin}, s.center + Vec2{s.margin, s.margin}};
    case ShapeKind::Ellipse: {
      Vec2 v = perp(s.axis);
      double hx = std::hypot(s.rx * s.axis.x, s.ry * v.x);
      double hy = std::hypot(s.rx * s.axis.y, s.ry * v.y);
      return {s.center - Vec2{hx, hy}, s.center + Vec2{hx, hy}};
    }
    case ShapeKind::Polygon: {
      Aabb b{s.vertices[0], s.vertices[0]};
      for (int i = 1; i < s.vertex_count; ++i) {
        b.lo = {std::min(b.lo.x, s.vertices[i].x), std::min(b.lo.y, s.vertices[i].y)};
        b.hi = {std::max(b.hi.x, s.vertices[i].x), std::max(b.hi.y, s.vertices[i].y)};
      }
      return b;
    }
  }
  return {};
}

std::vector<Vec2> outline(const Shape& s, int round_sides) {
  std::vector<Vec2> out;
  if (s.kind == ShapeKind::Polygon) {
    out.assign(s.vertices, s.vertices + s.vertex_count);
    return out;
  }
  const double rx = s.kind == ShapeKind::Circle ? s.radius : s.rx;
  const double ry = s.kind == ShapeKind::Circle ? s.radius : s.ry;
  for (int i = 0; i < round_sides; ++i) {
    const double t = 2 * kPi * i / round_sides;
    out.push_back(s.center + rotate({rx * std::cos(t), ry * std::sin(t)}, s.angle));
  }
  return out;
}

}  // namespace troupe::robocup
