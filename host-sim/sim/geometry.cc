#include "host-sim/sim/geometry.h"

#include <algorithm>

namespace troupe::sim {

double ray_segment(Vec2 o, Vec2 d, Vec2 a, Vec2 b) {
  Vec2 e = b - a;
  double den = cross(d, e);
  if (std::fabs(den) < 1e-15) return -1;  // parallel: a grazing ray does not stop on an edge
  Vec2 ao = a - o;
  const double nt = cross(ao, e), nu = cross(ao, d);
  // Most edges a ray is tested against it misses by far (behind it, or
  // beside the edge's ends): settled on the numerators, without the two
  // divisions, only where the quotients could not round back into range.
  const double sign = den > 0 ? 1 : -1, mag = std::fabs(den), slack = 1e-12 * mag;
  if (sign * nt < -slack || sign * nu < -slack || sign * nu > mag + slack) return -1;
  double t = nt / den;
  double u = nu / den;
  return (t >= 0 && u >= 0 && u <= 1) ? t : -1;
}

namespace {

// ray_polygon's loop, with each vertex's side of the ray's line from
// `side(i)`. A line crosses at most a few of a polygon's edges (two of a
// convex one): an edge whose ends lie clearly on one side is settled by the
// sides alone, as ray_segment would settle it (-1). kSide (m) is far above
// the rounding of these cross products and of ray_segment's own (about
// 1e-15 m at the ranges rays have), so only edges ray_segment surely misses
// are skipped: the same doubles.
template <typename Side>
double ray_polygon_sided(Vec2 o, Vec2 d, std::span<const Vec2> poly, Side side) {
  constexpr double kSide = 1e-9;
  const size_t n = poly.size();
  if (n == 0) return -1;
  const double first = side(0);
  double best = -1, sa = first;
  for (size_t i = 0; i < n; ++i) {
    const bool last = i + 1 == n;
    const double sb = last ? first : side(i + 1);
    if (!((sa > kSide && sb > kSide) || (sa < -kSide && sb < -kSide))) {
      const double t = ray_segment(o, d, poly[i], poly[last ? 0 : i + 1]);
      if (t >= 0 && (best < 0 || t < best)) best = t;
    }
    sa = sb;
  }
  return best;
}

}  // namespace

double ray_polygon(Vec2 o, Vec2 d, std::span<const Vec2> poly) {
  return ray_polygon_sided(o, d, poly, [&](size_t i) { return cross(d, poly[i] - o); });
}

double ray_polygon(Vec2 o, Vec2 d, std::span<const Vec2> poly, const Vec2* rel) {
  return ray_polygon_sided(o, d, poly, [&](size_t i) { return cross(d, rel[i]); });
}

bool point_in_polygon(Vec2 p, std::span<const Vec2> poly) {
  bool inside = false;
  for (size_t i = 0, n = poly.size(), j = n - 1; i < n; j = i++) {
    Vec2 a = poly[i], b = poly[j];
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) inside = !inside;
  }
  return inside;
}

namespace {

int orientation(Vec2 a, Vec2 b, Vec2 c) {
  double v = cross(b - a, c - a);
  return v > 1e-15 ? 1 : (v < -1e-15 ? -1 : 0);
}

bool on_segment(Vec2 a, Vec2 b, Vec2 p) {
  return std::min(a.x, b.x) - 1e-12 <= p.x && p.x <= std::max(a.x, b.x) + 1e-12 &&
         std::min(a.y, b.y) - 1e-12 <= p.y && p.y <= std::max(a.y, b.y) + 1e-12;
}

}  // namespace

bool segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  int o1 = orientation(a, b, c), o2 = orientation(a, b, d);
  int o3 = orientation(c, d, a), o4 = orientation(c, d, b);
  if (o1 != o2 && o3 != o4) return true;
  return (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) ||
         (o3 == 0 && on_segment(c, d, a)) || (o4 == 0 && on_segment(c, d, b));
}

bool polygons_overlap(std::span<const Vec2> p, std::span<const Vec2> q) {
  if (p.empty() || q.empty()) return false;
  for (size_t i = 0, n = p.size(); i < n; ++i) {
    for (size_t j = 0, m = q.size(); j < m; ++j) {
      if (segments_intersect(p[i], p[(i + 1) % n], q[j], q[(j + 1) % m])) return true;
    }
  }
  return point_in_polygon(p[0], q) || point_in_polygon(q[0], p);
}

bool segment_overlaps_box(Vec2 a, Vec2 b, Vec2 lo, Vec2 hi) {
  // Liang-Barsky clipping: the segment touches the box when some part of it
  // survives the four slabs.
  double t0 = 0, t1 = 1;
  Vec2 d = b - a;
  const double p[4] = {-d.x, d.x, -d.y, d.y};
  const double q[4] = {a.x - lo.x, hi.x - a.x, a.y - lo.y, hi.y - a.y};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0) {
      if (q[i] < 0) return false;
      continue;
    }
    double r = q[i] / p[i];
    if (p[i] < 0) {
      t0 = std::max(t0, r);
    } else {
      t1 = std::min(t1, r);
    }
    if (t0 > t1) return false;
  }
  return true;
}

bool polygon_overlaps_box(std::span<const Vec2> poly, Vec2 lo, Vec2 hi) {
  if (poly.empty()) return false;
  for (size_t i = 0, n = poly.size(); i < n; ++i) {
    if (segment_overlaps_box(poly[i], poly[(i + 1) % n], lo, hi)) return true;
  }
  // No edge touches the box: either the box is inside the polygon or apart.
  return point_in_polygon(0.5 * (lo + hi), poly);
}

}  // namespace troupe::sim
