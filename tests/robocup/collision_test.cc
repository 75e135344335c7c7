// Narrow phase: distances, penetrations, rays and mass properties of the
// primitives, checked against closed forms and brute-force sampling.
#include <gtest/gtest.h>

#include <vector>

#include "host-sim/robocup/physics/distance.h"
#include "host-sim/robocup/physics/raycast.h"
#include "host-sim/robocup/physics/shape.h"

namespace troupe::robocup {
namespace {

PlacedShape at(const Shape& s, Pose2 p = {}) {
  return place(s, p);
}

// The gap between two shapes by sampling their boundaries densely: a
// reference that shares no code with GJK.
std::vector<Vec2> boundary(const PlacedShape& s) {
  constexpr int kN = 720;
  std::vector<Vec2> out;
  if (s.kind == ShapeKind::Polygon) {
    for (int i = 0; i < s.vertex_count; ++i) {
      Vec2 a = s.vertices[i], b = s.vertices[(i + 1) % s.vertex_count];
      for (int k = 0; k < kN / s.vertex_count; ++k)
        out.push_back(a + (b - a) * (k * double(s.vertex_count) / kN));
    }
  } else if (s.kind == ShapeKind::Ellipse) {
    for (int k = 0; k < kN; ++k) {
      double t = 2 * kPi * k / kN;
      out.push_back(s.center + s.axis * (s.rx * std::cos(t)) + perp(s.axis) * (s.ry * std::sin(t)));
    }
  } else {
    for (int k = 0; k < kN; ++k) out.push_back(s.center + direction(2 * kPi * k / kN) * s.margin);
  }
  return out;
}

double sampled_gap(const PlacedShape& a, const PlacedShape& b) {
  double best = 1e9;
  for (Vec2 p : boundary(a)) {
    for (Vec2 q : boundary(b)) best = std::min(best, length(p - q));
  }
  return best;
}

TEST(Distance, CirclesMatchTheClosedForm) {
  Separation s = separation(at(make_circle({0, 0}, 0.5)), at(make_circle({2, 1}, 0.25)));
  EXPECT_NEAR(s.distance, std::sqrt(5.0) - 0.75, 1e-12);
  EXPECT_NEAR(s.normal.x, 2 / std::sqrt(5.0), 1e-12);
  EXPECT_NEAR(s.normal.y, 1 / std::sqrt(5.0), 1e-12);
}

TEST(Distance, CirclePenetrationComesFromTheCores) {
  Separation s = separation(at(make_circle({0, 0}, 0.5)), at(make_circle({0.8, 0}, 0.5)));
  EXPECT_NEAR(s.distance, -0.2, 1e-12);
  EXPECT_NEAR(s.points[0].x, 0.4, 1e-12);
}

TEST(Distance, BoxToCircleAndBoxToBox) {
  Shape box = make_rect({0, 0}, 2, 1);
  EXPECT_NEAR(separation(at(box), at(make_circle({3, 0}, 0.5))).distance, 1.5, 1e-9);
  // Corner to circle: corner (1, 0.5) to centre (2, 1.5).
  EXPECT_NEAR(separation(at(box), at(make_circle({2, 1.5}, 0.1))).distance, std::sqrt(2.0) - 0.1, 1e-9);
  // A box turned 45 degrees, its corner towards the first box's face.
  Shape diamond = make_rect({0, 0}, 1, 1, kPi / 4);
  EXPECT_NEAR(separation(at(box), at(diamond, {2, 0, 0})).distance, 1 - std::sqrt(0.5), 1e-9);
}

TEST(Distance, FlatFacesGiveTwoContactPointsSpanningTheOverlap) {
  Separation s = separation(at(make_rect({0, 0}, 1, 1)), at(make_rect({1.0001, 0.25}, 1, 1)));
  ASSERT_EQ(s.point_count, 2);
  EXPECT_NEAR(std::min(s.points[0].y, s.points[1].y), -0.25, 1e-9);
  EXPECT_NEAR(std::max(s.points[0].y, s.points[1].y), 0.5, 1e-9);
}

TEST(Distance, EllipsesAgreeWithSampling) {
  PlacedShape e = at(make_ellipse({0, 0}, 0.6, 0.2, 0.3));
  PlacedShape c = at(make_circle({0.9, 0.7}, 0.15));
  PlacedShape t;
  Shape tri;
  std::string error;
  const Vec2 pts[] = {{0, 0}, {0.4, 0.1}, {0.1, 0.5}};
  ASSERT_TRUE(make_polygon(pts, tri, error)) << error;
  t = at(tri, {-1.2, 0.3, 0.5});
  EXPECT_NEAR(separation(e, c).distance, sampled_gap(e, c), 2e-4);
  EXPECT_NEAR(separation(e, t).distance, sampled_gap(e, t), 2e-4);
}

TEST(Distance, DeepOverlapFindsTheLeastPenetration) {
  // Box cores overlap: the cheapest way out is along x by 0.3.
  Separation s = separation(at(make_rect({0, 0}, 1, 1)), at(make_rect({0.7, 0.1}, 1, 1)));
  EXPECT_NEAR(s.distance, -0.3, 1e-9);
  EXPECT_NEAR(s.normal.x, 1, 1e-9);
  // Ellipse into a box: a curved shape takes the sampled search.
  Separation e = separation(at(make_rect({0, 0}, 2, 2)), at(make_ellipse({0, 1.1}, 0.5, 0.2)));
  EXPECT_NEAR(e.distance, -0.1, 1e-6);
  EXPECT_NEAR(e.normal.y, 1, 1e-6);
}

TEST(Raycast, HitsEachPrimitiveAtItsSurface) {
  RayShapeHit h;
  ASSERT_TRUE(raycast(at(make_circle({5, 0}, 1)), {0, 0}, {1, 0}, 10, h));
  EXPECT_NEAR(h.distance, 4, 1e-12);
  EXPECT_NEAR(h.normal.x, -1, 1e-12);
  ASSERT_TRUE(raycast(at(make_ellipse({5, 0}, 2, 0.5)), {0, 0}, {1, 0}, 10, h));
  EXPECT_NEAR(h.distance, 3, 1e-12);
  ASSERT_TRUE(raycast(at(make_ellipse({0, 5}, 2, 0.5)), {0, 0}, {0, 1}, 10, h));
  EXPECT_NEAR(h.distance, 4.5, 1e-12);
  ASSERT_TRUE(raycast(at(make_rect({5, 0}, 2, 2)), {0, 0.5}, {1, 0}, 10, h));
  EXPECT_NEAR(h.distance, 4, 1e-12);
  EXPECT_FALSE(raycast(at(make_rect({5, 0}, 2, 2)), {0, 0}, {1, 0}, 3.9, h)) << "beyond max range";
  EXPECT_FALSE(raycast(at(make_rect({5, 0}, 2, 2)), {0, 0}, {-1, 0}, 10, h)) << "behind the ray";
  EXPECT_FALSE(raycast(at(make_circle({0, 0}, 1)), {0, 0}, {1, 0}, 10, h)) << "from inside";
}

TEST(Shapes, PolygonsMustBeConvexAndSmallEnough) {
  Shape s;
  std::string error;
  const Vec2 dart[] = {{0, 0}, {2, 1}, {0, 0.2}, {-2, 1}};
  EXPECT_FALSE(make_polygon(dart, s, error));
  EXPECT_NE(error.find("convex"), std::string::npos) << error;
  const Vec2 line[] = {{0, 0}, {1, 0}, {2, 0}};
  EXPECT_FALSE(make_polygon(line, s, error));
  std::vector<Vec2> many;
  for (int i = 0; i < 9; ++i) many.push_back(direction(2 * kPi * i / 9));
  EXPECT_FALSE(make_polygon(many, s, error));
  EXPECT_NE(error.find("3 to 8"), std::string::npos) << error;
  // Clockwise input is accepted and turned around.
  const Vec2 cw[] = {{0, 0}, {0, 1}, {1, 0}};
  EXPECT_TRUE(make_polygon(cw, s, error)) << error;
  EXPECT_GT(area_properties(s).area, 0);
}

TEST(Shapes, AreaPropertiesMatchClosedForms) {
  AreaProperties r = area_properties(make_rect({1, 0}, 2, 1));
  EXPECT_NEAR(r.area, 2, 1e-12);
  EXPECT_NEAR(r.centroid.x, 1, 1e-12);
  // (w^2 + h^2)/12 per unit area about the centroid, plus the offset.
  EXPECT_NEAR(r.second_moment, 2 * ((4 + 1) / 12.0 + 1), 1e-12);
  AreaProperties e = area_properties(make_ellipse({0, 0}, 2, 1));
  EXPECT_NEAR(e.area, 2 * kPi, 1e-12);
  EXPECT_NEAR(e.second_moment, 2 * kPi * 5 / 4, 1e-12);
}

}  // namespace
}  // namespace troupe::robocup
