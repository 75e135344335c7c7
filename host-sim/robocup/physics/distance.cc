#include "host-sim/robocup/physics/distance.h"

#include <algorithm>

namespace troupe::robocup {
namespace {

struct SimplexVertex {
  Vec2 a, b, w;  // support points on A, on B, and w = a - b
  int ia = -1, ib = -1;
  double u = 1;  // barycentric weight of the closest point
};

struct Simplex {
  SimplexVertex v[3];
  int count = 0;

  Vec2 closest() const {
    Vec2 p;
    for (int i = 0; i < count; ++i) p += v[i].w * v[i].u;
    return p;
  }
  void witnesses(Vec2& pa, Vec2& pb) const {
    pa = {};
    pb = {};
    for (int i = 0; i < count; ++i) {
      pa += v[i].a * v[i].u;
      pb += v[i].b * v[i].u;
    }
  }

  // Keeps the smallest sub-simplex whose hull holds the point of the
  // current simplex closest to the origin (Voronoi regions of its
  // vertices and edges), with barycentric weights. Returns false when the
  // origin lies inside the triangle.
  bool reduce() {
    if (count == 1) {
      v[0].u = 1;
      return true;
    }
    if (count == 2) {
      reduce_segment(0, 1);
      return true;
    }
    const Vec2 w1 = v[0].w, w2 = v[1].w, w3 = v[2].w;
    const Vec2 e12 = w2 - w1, e13 = w3 - w1, e23 = w3 - w2;
    const double d12_1 = dot(w2, e12), d12_2 = -dot(w1, e12);
    const double d13_1 = dot(w3, e13), d13_2 = -dot(w1, e13);
    const double d23_1 = dot(w3, e23), d23_2 = -dot(w2, e23);
    const double n123 = cross(e12, e13);
    const double d123_1 = n123 * cross(w2, w3), d123_2 = n123 * cross(w3, w1), d123_3 = n123 * cross(w1, w2);
    if (d12_2 <= 0 && d13_2 <= 0) return keep(0);
    if (d12_1 > 0 && d12_2 > 0 && d123_3 <= 0) return keep_edge(0, 1, d12_1, d12_2);
    if (d13_1 > 0 && d13_2 > 0 && d123_2 <= 0) return keep_edge(0, 2, d13_1, d13_2);
    if (d12_1 <= 0 && d23_2 <= 0) return keep(1);
    if (d13_1 <= 0 && d23_1 <= 0) return keep(2);
    if (d23_1 > 0 && d23_2 > 0 && d123_1 <= 0) return keep_edge(1, 2, d23_1, d23_2);
    return false;
  }

  void reduce_segment(int i, int j) {
    const Vec2 e = v[j].w - v[i].w;
    const double di = dot(v[j].w, e), dj = -dot(v[i].w, e);
    if (dj <= 0) {
      keep(i);
    } else if (di <= 0) {
      keep(j);
    } else {
      keep_edge(i, j, di, dj);
    }
  }
  bool keep(int i) {
    v[0] = v[i];
    v[0].u = 1;
    count = 1;
    return true;
  }
  bool keep_edge(int i, int j, double di, double dj) {
    SimplexVertex a = v[i], b = v[j];
    a.u = di / (di + dj);
    b.u = dj / (di + dj);
    v[0] = a;
    v[1] = b;
    count = 2;
    return true;
  }
};

SimplexVertex support_pair(const PlacedShape& a, const PlacedShape& b, Vec2 d) {
  SimplexVertex s;
  s.a = support(a, d, &s.ia);
  s.b = support(b, -d, &s.ib);
  s.w = s.a - s.b;
  return s;
}

// GJK: the closest points of the cores. False when the cores overlap.
bool core_distance(const PlacedShape& a, const PlacedShape& b, Vec2& pa, Vec2& pb) {
  Simplex sx;
  Vec2 d = b.center - a.center;
  if (length_squared(d) == 0) d = {1, 0};
  sx.v[0] = support_pair(a, b, -d);
  sx.count = 1;
  constexpr int kMaxIterations = 48;
  for (int it = 0; it < kMaxIterations; ++it) {
    if (!sx.reduce()) return false;
    const Vec2 v = sx.closest();
    const double vv = length_squared(v);
    if (vv < 1e-24) return false;
    const SimplexVertex w = support_pair(a, b, -v);
    // Converged when the new support point brings the hull no closer.
    if (vv - dot(v, w.w) <= 1e-12 * vv + 1e-20) break;
    bool duplicate = false;
    for (int i = 0; i < sx.count; ++i) {
      if (length_squared(sx.v[i].w - w.w) < 1e-24) duplicate = true;
    }
    if (duplicate) break;
    sx.v[sx.count++] = w;
  }
  sx.witnesses(pa, pb);
  return true;
}

double extent(const PlacedShape& s, Vec2 n) {
  return dot(support(s, n), n) + s.margin;
}

// Overlapping cores: the direction of least overlap among the polygons'
// face normals (exact for polygons) and sampled directions refined by a
// golden-section search (curved shapes).
Separation deep_penetration(const PlacedShape& a, const PlacedShape& b) {
  auto overlap = [&](Vec2 n) { return extent(a, n) + extent(b, -n); };
  double best = kUnboundedZ;
  Vec2 best_n{1, 0};
  auto consider = [&](Vec2 n) {
    double o = overlap(n);
    if (o < best) {
      best = o;
      best_n = n;
    }
  };
  for (int i = 0; i < a.vertex_count; ++i) {
    consider(-perp(normalized(a.vertices[(i + 1) % a.vertex_count] - a.vertices[i])));
  }
  for (int i = 0; i < b.vertex_count; ++i) {
    consider(perp(normalized(b.vertices[(i + 1) % b.vertex_count] - b.vertices[i])));
  }
  const bool curved = a.vertex_count == 0 || b.vertex_count == 0;
  if (curved) {
    constexpr int kSamples = 64;
    double best_angle = 0, best_sample = kUnboundedZ;
    for (int i = 0; i < kSamples; ++i) {
      double ang = 2 * kPi * i / kSamples;
      double o = overlap(direction(ang));
      if (o < best_sample) {
        best_sample = o;
        best_angle = ang;
      }
    }
    double lo = best_angle - 2 * kPi / kSamples, hi = best_angle + 2 * kPi / kSamples;
    constexpr double kGolden = 0.6180339887498949;
    for (int i = 0; i < 40; ++i) {
      double m1 = hi - kGolden * (hi - lo), m2 = lo + kGolden * (hi - lo);
      if (overlap(direction(m1)) < overlap(direction(m2))) {
        hi = m2;
      } else {
        lo = m1;
      }
    }
    consider(direction((lo + hi) / 2));
  }
  Separation s;
  s.distance = -best;
  s.normal = best_n;
  Vec2 pa = support(a, best_n) + best_n * a.margin;
  Vec2 pb = support(b, -best_n) - best_n * b.margin;
  s.points[0] = (pa + pb) / 2;
  return s;
}

// The polygon edge whose outward normal is within about 0.6 degrees of `n`,
// or -1.
int face_along(const PlacedShape& s, Vec2 n) {
  for (int i = 0; i < s.vertex_count; ++i) {
    Vec2 out = -perp(normalized(s.vertices[(i + 1) % s.vertex_count] - s.vertices[i]));
    if (dot(out, n) > 0.99995) return i;
  }
  return -1;
}

// Two flat faces against each other: the contact spans their overlap, so
// the solver gets both ends and no spurious torque.
void face_contact(const PlacedShape& a, const PlacedShape& b, Separation& s) {
  if (a.vertex_count == 0 || b.vertex_count == 0) return;
  int fa = face_along(a, s.normal), fb = face_along(b, -s.normal);
  if (fa < 0 || fb < 0) return;
  const Vec2 t = perp(s.normal);
  const Vec2 a0 = a.vertices[fa], a1 = a.vertices[(fa + 1) % a.vertex_count];
  const Vec2 b0 = b.vertices[fb], b1 = b.vertices[(fb + 1) % b.vertex_count];
  double lo = std::max(std::min(dot(a0, t), dot(a1, t)), std::min(dot(b0, t), dot(b1, t)));
  double hi = std::min(std::max(dot(a0, t), dot(a1, t)), std::max(dot(b0, t), dot(b1, t)));
  if (hi - lo < 1e-6) return;
  const Vec2 m = s.points[0];
  s.point_count = 2;
  s.points[0] = m + t * (lo - dot(m, t));
  s.points[1] = m + t * (hi - dot(m, t));
}

}  // namespace

Separation separation(const PlacedShape& a, const PlacedShape& b) {
  Vec2 pa, pb;
  if (!core_distance(a, b, pa, pb)) {
    Separation s = deep_penetration(a, b);
    face_contact(a, b, s);
    return s;
  }
  Separation s;
  const Vec2 d = pb - pa;
  const double core = length(d);
  s.normal = core > 1e-12 ? d / core : normalized(b.center - a.center);
  s.distance = core - a.margin - b.margin;
  const Vec2 sa = pa + s.normal * a.margin, sb = pb - s.normal * b.margin;
  s.points[0] = (sa + sb) / 2;
  face_contact(a, b, s);
  return s;
}

}  // namespace troupe::robocup
