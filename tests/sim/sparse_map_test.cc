// The sparse static map against the dense one on maps small enough for
// both: the same codes where rays read cells, the same coarse level, the
// same ranges ray by ray (bit for bit: the casters take the same steps),
// the same collisions and sensor readings in a whole world; and a map far
// larger than a dense one could be, held in a fraction of its cells. And
// a window of a map (what a process of a divided world holds), dense or
// sparse: inside it, what the whole map answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "host-sim/sim/static_map.h"
#include "host-sim/sim/world.h"
#include "tests/sim/scenes.h"

namespace troupe::sim {
namespace {

constexpr uint8_t kMarchFrom = StaticMap::kFreeBase + 3;  // the casters read cells below it

// Boxes and polygons of seeded sizes and places over [0, side]^2: long
// thin walls, blocks a few cells to metres across (whole 8 x 8 blocks
// inside them), rotated shapes, each solid, seen-only or barrier-only.
void fill_seeded(StaticMap& map, double side, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> at(0, side), size(0.02, 2.0), unit(0, 1);
  for (int i = 0; i < 80; ++i) {
    const Vec2 lo{at(rng), at(rng)};
    const double sx = size(rng), sy = i % 3 == 0 ? 0.1 * size(rng) : size(rng);
    const int kind = i % 4;  // 0, 1: solid; 2: seen only; 3: barrier only
    map.fill_box(lo, {lo.x + sx, lo.y + sy}, kind != 2, kind != 3);
  }
  for (int i = 0; i < 20; ++i) {
    const Vec2 c{at(rng), at(rng)};
    const double a = unit(rng) * kPi, r = size(rng);
    std::vector<Vec2> tri;
    for (int k = 0; k < 3; ++k)
      tri.push_back({c.x + r * std::cos(a + k * 2.1), c.y + r * std::sin(a + k * 2.1)});
    map.fill_polygon(tri, i % 2 == 0, true);
  }
}

// A square about `c` (m) turned by `a` (rad), its corners `r` m from `c`.
std::vector<Vec2> turned_square(Vec2 c, double a, double r) {
  std::vector<Vec2> square;
  for (int k = 0; k < 4; ++k)
    square.push_back({c.x + r * std::cos(a + k * kPi / 2), c.y + r * std::sin(a + k * kPi / 2)});
  return square;
}

// A dense map large enough for its coarse level (2,400 x 2,400 cells) and a
// sparse one, filled alike.
struct Pair {
  StaticMap dense, sparse;
  Pair(double side, double res, uint64_t seed) {
    dense.reset({0, 0}, {side, side}, res, MapStorage::Dense);
    sparse.reset({0, 0}, {side, side}, res, MapStorage::Sparse);
    fill_seeded(dense, side, seed);
    fill_seeded(sparse, side, seed);
    dense.finish();
    sparse.finish();
  }
};

TEST(SparseMap, HoldsTheDenseCodesWhereRaysReadThem) {
  Pair p(24, 0.01, 11);
  ASSERT_FALSE(p.dense.sparse());
  ASSERT_TRUE(p.dense.coarse());
  ASSERT_TRUE(p.sparse.sparse());
  ASSERT_EQ(p.dense.width(), p.sparse.width());
  ASSERT_EQ(p.dense.height(), p.sparse.height());
  const int w = p.dense.width(), h = p.dense.height();
  size_t stored = 0, shared = 0;
  for (int by = 0; by * StaticMap::kTile < h; ++by) {
    for (int bx = 0; bx * StaticMap::kTile < w; ++bx) {
      // The block's smallest dense code is its coarse code.
      uint8_t lowest = 255;
      for (int y = by * 8; y < std::min(h, by * 8 + 8); ++y) {
        for (int x = bx * 8; x < std::min(w, bx * 8 + 8); ++x) lowest = std::min(lowest, p.dense.code(x, y));
      }
      for (int y = by * 8; y < std::min(h, by * 8 + 8); ++y) {
        for (int x = bx * 8; x < std::min(w, bx * 8 + 8); ++x) {
          // Near obstacles every cell as dense; elsewhere the block's
          // coarse code stands for each of its cells.
          const uint8_t want = lowest < kMarchFrom ? p.dense.code(x, y) : lowest;
          ASSERT_EQ(p.sparse.code(x, y), want) << "cell " << x << ", " << y;
        }
      }
      (lowest < kMarchFrom ? stored : shared) += 1;
    }
  }
  // Both kinds are there, and the shared ones cost no cells.
  EXPECT_GT(stored, 1000u);
  EXPECT_GT(shared, 4 * stored);
  EXPECT_LT(p.sparse.memory_bytes(), p.dense.memory_bytes() / 4);
}

TEST(SparseMap, CastsTheSameRangesRayByRay) {
  Pair p(24, 0.01, 12);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> at(-1, 25), ang(-kPi, kPi), range(0.05, 30);
  std::vector<RayQuery> rays;
  for (int i = 0; i < 20000; ++i) {
    const double a = ang(rng);
    rays.push_back({{at(rng), at(rng)}, {std::cos(a), std::sin(a)}, float(range(rng))});
  }
  // A fan from one point, as a laser casts it (shared first step).
  for (int i = 0; i < 360; ++i)
    rays.push_back({{12, 12}, {std::cos(i * kPi / 180), std::sin(i * kPi / 180)}, 20});
  for (uint8_t mask : {StaticMap::kRangerMask, StaticMap::kObstacleMask, StaticMap::kAnyMask,
                       uint8_t(1u << StaticMap::kVisible)}) {
    SCOPED_TRACE(int(mask));
    std::vector<float> dense(rays.size()), sparse(rays.size());
    p.dense.cast_batch(rays, mask, dense.data());
    p.sparse.cast_batch(rays, mask, sparse.data());
    size_t hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(sparse[i], dense[i]) << "ray " << i;
      hits += dense[i] < rays[i].max_range;
      if (i % 20 == 0) {
        const RayQuery& r = rays[i];
        ASSERT_EQ(p.sparse.cast(r.origin, r.dir, r.max_range, mask), dense[i]) << "ray " << i;
        ASSERT_EQ(p.sparse.cast_per_cell(r.origin, r.dir, r.max_range, mask),
                  p.dense.cast_per_cell(r.origin, r.dir, r.max_range, mask))
            << "ray " << i;
      }
    }
    EXPECT_GT(hits, rays.size() / 4);  // the rays do meet the obstacles
  }
}

TEST(SparseMap, CollisionQueriesAndClearanceAgree) {
  Pair p(24, 0.01, 13);
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> at(0, 24), ang(-kPi, kPi), len(0.01, 1.5);
  int overlapping = 0;
  for (int i = 0; i < 5000; ++i) {
    const Vec2 c{at(rng), at(rng)};
    const double a = ang(rng), r = 0.5 * len(rng);
    const std::vector<Vec2> square = turned_square(c, a, r);
    const bool hit = p.dense.overlaps(square);
    ASSERT_EQ(p.sparse.overlaps(square), hit) << "square " << i;
    overlapping += hit;
    const Vec2 end{c.x + len(rng) * std::cos(a), c.y + len(rng) * std::sin(a)};
    ASSERT_EQ(p.sparse.segment_hits(c, end), p.dense.segment_hits(c, end)) << "segment " << i;
    // Both are lower bounds on the distance to an obstacle; the sparse one
    // answers from the coarse level wherever the block is clear.
    for (double enough : {0.0, 0.05, 1e300}) {
      const double sparse = p.sparse.clearance(c, enough), dense = p.dense.clearance(c, enough);
      ASSERT_EQ(sparse == 0, dense == 0) << "point " << i;
      if (enough == 0.0) {
        ASSERT_EQ(sparse, dense) << "point " << i;
      }
    }
  }
  EXPECT_GT(overlapping, 100);
  EXPECT_LT(overlapping, 4900);
}

// A world whose dense map reads its coarse level (2,500 x 2,500 cells):
// a seeded bitmap floor and a bordered room; robots with every sensor
// driving about, some into the walls and each other.
WorldDesc sensor_world(MapStorage storage) {
  WorldDesc d = test::room(24, 24, 0.02);
  d.map_storage = storage;
  auto img = std::make_shared<world::GrayImage>();
  img->width = img->height = 240;
  img->pixels.assign(240 * 240, 255);
  std::mt19937_64 rng(9);
  std::uniform_int_distribution<int> at(0, 230), size(1, 12);
  for (int i = 0; i < 150; ++i) {
    const int x0 = at(rng), y0 = at(rng), sx = size(rng), sy = size(rng);
    for (int y = y0; y < std::min(240, y0 + sy); ++y) {
      for (int x = x0; x < std::min(240, x0 + sx); ++x) img->pixels[size_t(y) * 240 + size_t(x)] = 0;
    }
  }
  StaticDesc floor;
  floor.name = "floor";
  floor.size = {47.9, 47.9};
  floor.bitmap = std::make_shared<BitmapDesc>();
  floor.bitmap->image = img;
  floor.look.color = 0x206020;
  floor.look.fiducial_id = 7;
  d.statics.push_back(floor);
  // The same bitmap again, small and turned: rasterized a polygon per run.
  StaticDesc annex = floor;
  annex.name = "annex";
  annex.size = {12, 12};
  annex.pose = {10, -12, 0.5};
  d.statics.push_back(annex);
  std::uniform_real_distribution<double> pos(-22, 22), ang(-kPi, kPi), speed(0.2, 2);
  for (int i = 0; i < 12; ++i) {
    RobotDesc r = test::robot("r" + std::to_string(i), {pos(rng), pos(rng), ang(rng)}, 0.3);
    r.rangers.push_back(test::laser(181, kPi, 8));
    r.fiducials.push_back({});
    r.blobfinders.push_back({});
    BumperDesc bumper;
    bumper.segments = {{{0.16, 0, 0}, 0.3}, {{-0.16, 0, kPi}, 0.3}};
    r.bumpers.push_back(bumper);
    r.cameras.push_back({});
    r.initial_velocity = {speed(rng), 0, 0.3 * ang(rng)};
    r.look.fiducial_id = i + 1;
    d.robots.push_back(r);
  }
  return d;
}

TEST(SparseMap, AWholeWorldSeesAndCollidesAlike) {
  World dense(sensor_world(MapStorage::Dense), Random(3));
  World sparse(sensor_world(MapStorage::Sparse), Random(3));
  ASSERT_FALSE(dense.map().sparse());
  ASSERT_TRUE(dense.map().coarse());
  ASSERT_TRUE(sparse.map().sparse());
  for (World* w : {&dense, &sparse}) {
    for (uint32_t k = 0; k < 12; ++k) {
      for (SensorKind kind : {SensorKind::Ranger, SensorKind::Fiducial, SensorKind::Blobfinder,
                              SensorKind::Bumper, SensorKind::Camera})
        w->set_wanted({kind, k}, true);
    }
  }
  int stalls = 0, wall_hits = 0;
  for (int step = 0; step < 60; ++step) {
    dense.step();
    sparse.step();
    for (RobotId i = 0; i < 12; ++i) {
      const RobotState &a = dense.state(i), &b = sparse.state(i);
      ASSERT_EQ(a.pose.x, b.pose.x) << "step " << step << " robot " << i;
      ASSERT_EQ(a.pose.y, b.pose.y);
      ASSERT_EQ(a.pose.a, b.pose.a);
      ASSERT_EQ(a.stalled, b.stalled);
      stalls += a.stalled;
      const RangerView ra = dense.ranger(i), rb = sparse.ranger(i);
      ASSERT_TRUE(std::equal(ra.ranges.begin(), ra.ranges.end(), rb.ranges.begin(), rb.ranges.end()));
      ASSERT_TRUE(std::equal(ra.intensities.begin(), ra.intensities.end(), rb.intensities.begin(),
                             rb.intensities.end()));
      for (float r : ra.ranges) wall_hits += r < 8;
      const FiducialView fa = dense.fiducial(i), fb = sparse.fiducial(i);
      ASSERT_EQ(fa.readings.size(), fb.readings.size());
      for (size_t k = 0; k < fa.readings.size(); ++k) {
        ASSERT_EQ(fa.readings[k].id, fb.readings[k].id);
        ASSERT_EQ(fa.readings[k].range, fb.readings[k].range);
      }
      const BlobView ba = dense.blobfinder(i), bb = sparse.blobfinder(i);
      ASSERT_EQ(ba.blobs.size(), bb.blobs.size());
      for (size_t k = 0; k < ba.blobs.size(); ++k) {
        ASSERT_EQ(ba.blobs[k].area, bb.blobs[k].area);
        ASSERT_EQ(ba.blobs[k].range, bb.blobs[k].range);
      }
      ASSERT_EQ(dense.bumper(i).pressed, sparse.bumper(i).pressed);
      const CameraView ca = dense.camera(i), cb = sparse.camera(i);
      ASSERT_TRUE(std::equal(ca.rgb.begin(), ca.rgb.end(), cb.rgb.begin(), cb.rgb.end()));
      ASSERT_TRUE(std::equal(ca.depth.begin(), ca.depth.end(), cb.depth.begin(), cb.depth.end()));
    }
  }
  EXPECT_GT(stalls, 0);  // the robots did run into things
  EXPECT_GT(wall_hits, 1000);
  EXPECT_LT(sparse.map().memory_bytes(), dense.map().memory_bytes() / 2);
}

TEST(SparseMap, AMapBeyondDenseSizesIsHeldInAFractionOfItsCells) {
  // 300 x 300 m at 0.01 m: 900 million cells, a few rooms' walls.
  StaticMap map;
  map.reset({0, 0}, {300, 300}, 0.01);
  ASSERT_TRUE(map.sparse());  // by size alone
  for (int i = 0; i < 10; ++i) {
    const double x = 20 + 25 * i, y = 150;
    for (auto [lo, hi] : {std::pair<Vec2, Vec2>{{x, y}, {x + 10, y + 0.1}},
                          {{x, y + 8}, {x + 10, y + 8.1}},
                          {{x, y}, {x + 0.1, y + 8.1}},
                          {{x + 9.9, y}, {x + 10, y + 8.1}}})
      map.fill_box(lo, hi, true, true);
  }
  map.finish();
  const size_t cells = size_t(map.width()) * size_t(map.height());
  EXPECT_GT(cells, size_t(800) << 20);
  EXPECT_LT(map.memory_bytes(), cells / 10);
  // A ray from inside the first room to its east wall, and one along the
  // whole map's open south.
  EXPECT_NEAR(map.cast({25, 154}, {1, 0}, 100), 4.9, 0.011);
  EXPECT_EQ(map.cast({1, 1}, {1, 0}, 250), 250);
  EXPECT_TRUE(map.occupied(int(20.05 / 0.01), int(154 / 0.01)));
  EXPECT_FALSE(map.occupied(int(25 / 0.01), int(154 / 0.01)));
}

// The whole dense map, and its window [6, 4]-[18, 20] m held dense and
// sparse, filled alike.
struct Windows {
  static constexpr double kSide = 24, kRes = 0.01;
  StaticMap whole, dense, sparse;
  explicit Windows(uint64_t seed) {
    const Vec2 window[2] = {{6, 4}, {18, 20}};
    whole.reset({0, 0}, {kSide, kSide}, kRes, MapStorage::Dense);
    dense.reset({0, 0}, {kSide, kSide}, kRes, MapStorage::Dense, window);
    sparse.reset({0, 0}, {kSide, kSide}, kRes, MapStorage::Sparse, window);
    for (StaticMap* m : {&whole, &dense, &sparse}) {
      fill_seeded(*m, kSide, seed);
      m->finish();
    }
  }
  // Where a window reads what the whole map holds: the distance field
  // saturates at 253 cells and a coarse block adds 8, so 2.64 m in.
  static bool inner(Vec2 p) { return p.x >= 8.64 && p.x <= 15.36 && p.y >= 6.64 && p.y <= 17.36; }
};

TEST(MapWindow, HoldsOnlyItsBlocksAndTheWholeMapsCodesInside) {
  Windows m(21);
  EXPECT_FALSE(m.whole.windowed());
  EXPECT_TRUE(m.dense.windowed());
  EXPECT_FALSE(m.dense.sparse());
  EXPECT_TRUE(m.sparse.sparse());
  // The same grid and coarse reading as the whole map.
  EXPECT_EQ(m.dense.width(), m.whole.width());
  EXPECT_EQ(m.dense.origin().x, m.whole.origin().x);
  EXPECT_EQ(m.dense.coarse(), m.whole.coarse());
  // A third of the area (12 x 16 of 24 x 24 m), a third of the cells.
  EXPECT_LT(m.dense.memory_bytes(), m.whole.memory_bytes() / 2);
  EXPECT_GT(m.dense.memory_bytes(), m.whole.memory_bytes() / 4);
  size_t obstacles = 0;
  for (int y = 664; y <= 1736; ++y) {
    for (int x = 864; x <= 1536; ++x) {
      ASSERT_EQ(m.dense.code(x, y), m.whole.code(x, y)) << "cell " << x << ", " << y;
      obstacles += m.whole.occupied(x, y);
    }
  }
  EXPECT_GT(obstacles, 1000u);  // there is something to get wrong
  // Beyond the window nothing is held: a snapshot's walk passes it.
  EXPECT_TRUE(m.dense.block_free(0, 0));
  EXPECT_TRUE(m.dense.block_free(2999 / 8, 2999 / 8));
}

TEST(MapWindow, CastsAndCollidesInsideAsTheWholeMap) {
  Windows m(22);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> x_at(8.64, 15.36), y_at(6.64, 17.36), ang(-kPi, kPi), range(0.05, 4),
      len(0.01, 1.5);
  std::vector<RayQuery> rays;
  while (rays.size() < 20000) {
    const double a = ang(rng);
    const RayQuery r{{x_at(rng), y_at(rng)}, {std::cos(a), std::sin(a)}, float(range(rng))};
    if (Windows::inner(r.origin + double(r.max_range) * r.dir)) rays.push_back(r);
  }
  for (int i = 0; i < 360; ++i)
    rays.push_back({{12, 12}, {std::cos(i * kPi / 180), std::sin(i * kPi / 180)}, 3});
  std::vector<float> whole(rays.size()), dense(rays.size()), sparse(rays.size());
  m.whole.cast_batch(rays, StaticMap::kRangerMask, whole.data());
  m.dense.cast_batch(rays, StaticMap::kRangerMask, dense.data());
  m.sparse.cast_batch(rays, StaticMap::kRangerMask, sparse.data());
  size_t hits = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(dense[i], whole[i]) << "ray " << i;
    ASSERT_EQ(sparse[i], whole[i]) << "ray " << i;
    hits += whole[i] < rays[i].max_range;
    if (i % 20 == 0) {
      const RayQuery& r = rays[i];
      ASSERT_EQ(m.dense.cast(r.origin, r.dir, r.max_range), whole[i]) << "ray " << i;
      ASSERT_EQ(m.dense.cast_per_cell(r.origin, r.dir, r.max_range),
                m.whole.cast_per_cell(r.origin, r.dir, r.max_range))
          << "ray " << i;
    }
  }
  EXPECT_GT(hits, rays.size() / 4);
  for (int i = 0; i < 5000; ++i) {
    const Vec2 c{x_at(rng), y_at(rng)};
    const double a = ang(rng), r = 0.5 * len(rng);
    const std::vector<Vec2> square = turned_square(c, a, r);
    if (!Windows::inner(square[0]) || !Windows::inner(square[2])) continue;
    ASSERT_EQ(m.dense.overlaps(square), m.whole.overlaps(square)) << "square " << i;
    for (double enough : {0.0, 0.05, 1e300})
      ASSERT_EQ(m.dense.clearance(c, enough), m.whole.clearance(c, enough)) << "point " << i;
  }
}

TEST(MapWindow, RaysLeavingTheWindowEndAtItsEdge) {
  Windows m(23);
  // From inside across the edge, from outside in, and wholly outside: a
  // window knows nothing beyond its edge, as a grid knows nothing beyond
  // its own, and reads nothing there.
  const std::vector<RayQuery> rays = {
      {{12, 12}, {1, 0}, 20}, {{12, 12}, {0, -1}, 20}, {{1, 1}, {1, 0}, 30},      {{1, 12}, {1, 0}, 30},
      {{23, 23}, {-1, 0}, 3}, {{30, 30}, {-1, 0}, 3},  {{12, 12}, {0.6, 0.8}, 40}};
  for (const StaticMap* map : {&m.dense, &m.sparse}) {
    std::vector<float> out(rays.size());
    map->cast_batch(rays, StaticMap::kRangerMask, out.data());
    for (size_t i = 0; i < rays.size(); ++i) {
      const RayQuery& r = rays[i];
      EXPECT_GE(out[i], 0) << "ray " << i;
      EXPECT_LE(out[i], r.max_range) << "ray " << i;
      EXPECT_EQ(map->cast(r.origin, r.dir, r.max_range), out[i]) << "ray " << i;
      EXPECT_EQ(map->cast_per_cell(r.origin, r.dir, r.max_range), out[i]) << "ray " << i;
    }
    // Wholly outside the window: nothing there.
    EXPECT_EQ(out[5], 3.0f);
    EXPECT_EQ(out[4], 3.0f);
  }
}

}  // namespace
}  // namespace troupe::sim
