// Rangers among many robots: the per-step robot layer (robot_layer.h), the
// per-robot candidates and the plain test of every robot against every beam
// give the same ranges and intensities, beam by beam and bit for bit, on
// random packed crowds of moving robots of several shapes (some with a
// polygon inside another); and the ray-edge and ray-polygon tests under all
// three give what their plain formulas give.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "host-sim/sim/geometry.h"
#include "host-sim/sim/robot_layer.h"
#include "host-sim/sim/world.h"
#include "tests/sim/scenes.h"

namespace troupe::sim {
namespace {

using How = World::RangerRobots;

// A crowd of `n` robots packed about `pitch` m apart (jittered, so some
// overlap and some leave gaps) in a walled room, from `seed`: squares and
// triangles of several sizes and headings, a few invisible to rangers, each
// with a sonar ring or a laser (some with bearing noise).
WorldDesc packed_crowd(uint64_t seed, int n, double pitch) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  WorldDesc d = test::room(6, 5);
  const int cols = int(std::ceil(std::sqrt(double(n))));
  for (int i = 0; i < n; ++i) {
    const double x = (i % cols - 0.5 * cols) * pitch + (u(rng) - 0.5) * 0.3 * pitch;
    const double y = (i / cols - 0.5 * cols) * pitch + (u(rng) - 0.5) * 0.3 * pitch;
    const double side = 0.1 + 0.2 * u(rng);
    RobotDesc r = test::robot("r" + std::to_string(i), {x, y, (u(rng) - 0.5) * 2 * kPi}, side);
    if (u(rng) < 0.3) r.polygons = {{{-side / 2, -side / 2}, {side / 2, 0}, {-side / 2, side / 2}}};
    if (u(rng) < 0.3) {
      // A second polygon inside the first (as a laser's block sits inside
      // a Pioneer's): rays from outside meet the outer one first.
      if (r.polygons.empty())
        r.polygons = {
            {{-side / 2, -side / 2}, {side / 2, -side / 2}, {side / 2, side / 2}, {-side / 2, side / 2}}};
      const double c = -side / 8, h = side / 16;
      r.polygons.push_back({{c - h, -h}, {c + h, -h}, {c + h, h}, {c - h, h}});
    }
    r.look.ranger_return = u(rng) < 0.1 ? -1 : (u(rng) < 0.5 ? 0.25 : 0.5);
    if (u(rng) < 0.7) {
      RangerDesc ring;
      for (int k = 0; k < 12; ++k) {
        TransducerDesc t;
        const double a = k * kPi / 6;
        t.pose = {0.5 * side * std::cos(a), 0.5 * side * std::sin(a), a};
        t.range_max = 2;
        ring.transducers.push_back(t);
      }
      r.rangers.push_back(ring);
    } else {
      r.rangers.push_back(test::laser(91, 1.5 * kPi, 4));
      if (u(rng) < 0.5) r.rangers.edit_back().transducers[0].noise_angle = 0.05;
    }
    d.robots.push_back(r);
  }
  return d;
}

struct Scans {
  std::vector<float> ranges, intensities;
};

// Steps the world `steps` times with seeded random commands, finding the
// robots in the beams `how`, and keeps every wanted ranger's beams after
// each step: every ranger's, or only ranger `only`'s.
Scans run(const WorldDesc& d, How how, uint64_t seed, int steps, int64_t only = -1) {
  World w(d, Random(seed));
  w.set_ranger_robots(how);
  for (RobotId i = 0; i < w.robot_count(); ++i) {
    const IndexRange r = w.robot(i).rangers;
    for (uint32_t k = r.first; k < r.first + r.count; ++k) {
      if (only < 0 || only == int64_t(k)) w.set_wanted({SensorKind::Ranger, k}, true);
    }
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Scans out;
  for (int s = 0; s < steps; ++s) {
    for (RobotId i = 0; i < w.robot_count(); ++i) w.command(i, Command::velocity(0.5 * u(rng), 0, u(rng)));
    w.step();
    for (RobotId i = 0; i < w.robot_count(); ++i) {
      const IndexRange r = w.robot(i).rangers;
      for (uint32_t k = r.first; k < r.first + r.count; ++k) {
        if (only >= 0 && only != int64_t(k)) continue;
        const RangerView v = w.ranger(k);
        out.ranges.insert(out.ranges.end(), v.ranges.begin(), v.ranges.end());
        out.intensities.insert(out.intensities.end(), v.intensities.begin(), v.intensities.end());
      }
    }
  }
  return out;
}

// Bit for bit: the same float, not merely a close one.
void expect_same_beams(const Scans& want, const Scans& got, const char* how) {
  ASSERT_EQ(want.ranges.size(), got.ranges.size());
  size_t differ = 0, first = 0;
  for (size_t b = 0; b < want.ranges.size(); ++b) {
    const bool same = std::memcmp(&want.ranges[b], &got.ranges[b], sizeof(float)) == 0 &&
                      std::memcmp(&want.intensities[b], &got.intensities[b], sizeof(float)) == 0;
    if (!same && differ++ == 0) first = b;
  }
  EXPECT_EQ(differ, 0u) << how << ": first at beam " << first << ": " << got.ranges[first] << " ("
                        << got.intensities[first] << ") against " << want.ranges[first] << " ("
                        << want.intensities[first] << ")";
}

TEST(RangerRobots, LayerAndCandidatesMatchEveryRobotAgainstEveryBeam) {
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const WorldDesc d = packed_crowd(seed, 120, seed % 2 ? 0.25 : 0.4);
    const Scans every = run(d, How::Every, seed, 4);
    // The crowd is in the beams: most beams end on a robot (returns 0.25
    // and 0.5; the walls return 1), so the comparison is about robots.
    size_t on_robots = 0;
    for (float i : every.intensities) on_robots += i == 0.25f || i == 0.5f;
    EXPECT_GT(on_robots, every.intensities.size() / 2);
    expect_same_beams(every, run(d, How::Layer, seed, 4), "layer");
    expect_same_beams(every, run(d, How::Candidates, seed, 4), "candidates");
    expect_same_beams(every, run(d, How::Auto, seed, 4), "auto");
  }
}

TEST(RangerRobots, RangersCastTogetherMatchEachCastAlone) {
  // A step casts the rays of many rangers as one batch (several robots'
  // rings and lasers, the batch cast in the middle of a laser's beams);
  // a ranger wanted alone is cast alone. Each must get the same beams.
  for (uint64_t seed = 1; seed <= 2; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const WorldDesc d = packed_crowd(seed, 36, seed % 2 ? 0.5 : 1.0);
    const Scans together = run(d, How::Auto, seed, 3);
    Scans alone;
    const int64_t count = int64_t(d.robots.size());  // one ranger per robot
    for (int64_t k = 0; k < count; ++k) {
      const Scans one = run(d, How::Auto, seed, 3, k);
      ASSERT_FALSE(one.ranges.empty());
      alone.ranges.insert(alone.ranges.end(), one.ranges.begin(), one.ranges.end());
      alone.intensities.insert(alone.intensities.end(), one.intensities.begin(), one.intensities.end());
    }
    // `together` holds step by step every ranger; `alone` ranger by ranger
    // every step: reorder before comparing.
    ASSERT_EQ(together.ranges.size(), alone.ranges.size());
    Scans regrouped;
    std::vector<size_t> beams, first_alone;
    size_t at = 0;
    for (const RobotDesc& r : d.robots) {
      size_t n = 0;
      for (const TransducerDesc& t : r.rangers[0].transducers) n += size_t(t.samples);
      beams.push_back(n);
      first_alone.push_back(at);
      at += 3 * n;
    }
    for (int s = 0; s < 3; ++s) {
      for (size_t k = 0; k < beams.size(); ++k) {
        const size_t from = first_alone[k] + size_t(s) * beams[k];
        regrouped.ranges.insert(regrouped.ranges.end(), alone.ranges.begin() + long(from),
                                alone.ranges.begin() + long(from + beams[k]));
        regrouped.intensities.insert(regrouped.intensities.end(), alone.intensities.begin() + long(from),
                                     alone.intensities.begin() + long(from + beams[k]));
      }
    }
    // Walls and robots both end beams here, so both parts are compared.
    size_t on_walls = 0, on_robots = 0;
    for (float i : together.intensities) {
      on_walls += i == 1.0f;
      on_robots += i == 0.25f || i == 0.5f;
    }
    EXPECT_GT(on_walls, 0u);
    EXPECT_GT(on_robots, 0u);
    expect_same_beams(regrouped, together, "cast together");
  }
}

TEST(RangerRobots, ABeamFromOutsideTheLayerIsClippedIntoIt) {
  // The layer's grid spans the circles of robots rangers see; the sensing
  // robot here is invisible to rangers, so its beams start outside the grid.
  WorldDesc d = test::room(6, 5);
  RobotDesc eye = test::robot("eye", {-5, 0, 0}, 0.2);
  eye.look.ranger_return = -1;
  eye.rangers.push_back(test::laser(3, 0.2, 10));
  d.robots.push_back(eye);
  for (int i = 0; i < 30; ++i) {
    d.robots.push_back(
        test::robot("c" + std::to_string(i), {2 + 0.3 * (i % 5), -0.6 + 0.3 * (i / 5), 0}, 0.2));
    d.robots.back().look.ranger_return = 0.5;
  }
  World w(d, Random(1));
  w.set_ranger_robots(How::Layer);
  w.set_wanted({SensorKind::Ranger, 0}, true);
  w.refresh_sensors();
  const RangerView v = w.ranger(0);
  // The middle beam runs along y = 0 to the face x = 1.9 of the robot at (2, 0).
  EXPECT_NEAR(v.ranges[1], 1.9 - (-5), 1e-6);
  EXPECT_FLOAT_EQ(v.intensities[1], 0.5f);
}

// The ray-edge test as plainly written: both quotients, then the range
// checks. ray_segment skips the divisions for edges missed by far and must
// give the same double for every other.
double ray_segment_plain(Vec2 o, Vec2 d, Vec2 a, Vec2 b) {
  const Vec2 e = b - a;
  const double den = cross(d, e);
  if (std::fabs(den) < 1e-15) return -1;
  const Vec2 ao = a - o;
  const double t = cross(ao, e) / den, u = cross(ao, d) / den;
  return (t >= 0 && u >= 0 && u <= 1) ? t : -1;
}

TEST(RaySegment, SkippingTheDivisionsChangesNoResult) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-2, 2), ang(-kPi, kPi);
  size_t hits = 0, n = 0;
  for (int i = 0; i < 200000; ++i) {
    const double a0 = ang(rng);
    const Vec2 o{u(rng), u(rng)}, d{std::cos(a0), std::sin(a0)};
    Vec2 a{u(rng), u(rng)}, b{u(rng), u(rng)};
    // Every fourth edge ends on the ray, or starts at its origin: the
    // quotients land on 0 or 1, where rounding decides.
    if (i % 4 == 1) a = o + 1.5 * d;
    if (i % 4 == 2) b = o + 0.25 * d;
    if (i % 4 == 3) a = o;
    const double want = ray_segment_plain(o, d, a, b), got = ray_segment(o, d, a, b);
    ++n;
    hits += want >= 0;
    ASSERT_EQ(std::memcmp(&want, &got, sizeof want), 0) << "case " << i << ": " << got << " against " << want;
  }
  EXPECT_GT(hits, n / 10);  // both outcomes are exercised
  EXPECT_LT(hits, n * 9 / 10);
}

// ray_polygon skips the edges whose ends lie clearly on one side of the
// ray's line; it must give what testing every edge gives, to the bit, also
// for rays through a vertex, along an edge or from a vertex.
double ray_polygon_every_edge(Vec2 o, Vec2 d, const std::vector<Vec2>& poly) {
  double best = -1;
  for (size_t i = 0; i < poly.size(); ++i) {
    const double t = ray_segment_plain(o, d, poly[i], poly[(i + 1) % poly.size()]);
    if (t >= 0 && (best < 0 || t < best)) best = t;
  }
  return best;
}

TEST(RayPolygon, SkippingEdgesOnOneSideChangesNoResult) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-1, 1), ang(-kPi, kPi);
  size_t hits = 0, n = 0;
  for (int i = 0; i < 100000; ++i) {
    // A star-shaped polygon of 3 to 9 vertices about the origin, 0.05 to
    // 0.5 m out (convex or not), seen from up to 8 m away.
    std::vector<Vec2> poly;
    const int count = 3 + int(rng() % 7);
    const double a0 = ang(rng);
    for (int k = 0; k < count; ++k) {
      const double a = a0 + 2 * kPi * (k + 0.4 * u(rng)) / count, r = 0.275 + 0.225 * u(rng);
      poly.push_back({r * std::cos(a), r * std::sin(a)});
    }
    Vec2 o{8 * u(rng), 8 * u(rng)};
    double heading = ang(rng);
    const Vec2 v = poly[rng() % poly.size()], w = poly[(rng() % poly.size())];
    // Rays aimed at a vertex, along an edge's line, from a vertex, or anywhere.
    if (i % 4 == 0) heading = std::atan2(v.y - o.y, v.x - o.x);
    if (i % 4 == 1 && !(v.x == w.x && v.y == w.y)) {
      o = v + 2 * (v - w);
      heading = std::atan2(w.y - v.y, w.x - v.x);
    }
    if (i % 4 == 2) o = v;
    const Vec2 d{std::cos(heading), std::sin(heading)};
    // Also with the vertices less the origin given, as the candidates' way
    // gives them for all the beams from one origin.
    std::vector<Vec2> rel;
    for (Vec2 p : poly) rel.push_back(p - o);
    const double want = ray_polygon_every_edge(o, d, poly), got = ray_polygon(o, d, poly),
                 got_rel = ray_polygon(o, d, poly, rel.data());
    ++n;
    hits += want >= 0;
    ASSERT_EQ(std::memcmp(&want, &got, sizeof want), 0) << "case " << i << ": " << got << " against " << want;
    ASSERT_EQ(std::memcmp(&want, &got_rel, sizeof want), 0)
        << "case " << i << ": " << got_rel << " against " << want;
  }
  EXPECT_GT(hits, n / 10);  // both outcomes are exercised
  EXPECT_LT(hits, n * 9 / 10);
}

TEST(RobotLayer, AnEmptyLayerWalksNoCell) {
  SpatialHash hash;
  hash.reset({-1, -1}, {1, 1}, 0.5);
  hash.build({}, {}, {});
  RobotLayer layer;
  layer.build(hash, 1);
  int cells = 0;
  layer.walk({0, 0}, {1, 0}, 5, [&](std::span<const RobotLayer::Entry>, double) {
    ++cells;
    return 5.0;
  });
  EXPECT_EQ(cells, 0);
}

}  // namespace
}  // namespace troupe::sim
