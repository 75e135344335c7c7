// The robots' spatial hash kept dense (a table of every cell) and sparse
// (robots sorted by row and column, found by binary search) must give the
// engine the same robots in the same order for every query, since rangers
// settle near-ties in the hash's order.
#include "host-sim/sim/spatial_hash.h"

#include <gtest/gtest.h>

#include <random>
#include <utility>
#include <vector>

namespace troupe::sim {
namespace {

struct Robots {
  std::vector<Vec2> centres;
  std::vector<double> radii;
  std::vector<uint32_t> flags;
};

// `n` robots in [-20, 20] m each way, some beyond the grid's [-15, 15] m
// (kept in its border cells), a few left out (radius < 0), several sharing
// a cell; radii 0.1 to 0.5 m.
Robots random_robots(size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(-20, 20), rad(0.1, 0.5);
  Robots r;
  for (size_t i = 0; i < n; ++i) {
    Vec2 c{pos(rng), pos(rng)};
    if (i % 7 == 3 && i > 0) c = r.centres[i - 1] + Vec2{0.01, -0.02};  // the cell of the one before
    r.centres.push_back(c);
    r.radii.push_back(i % 11 == 5 ? -1.0 : rad(rng));
    r.flags.push_back(uint32_t(i % 3));
  }
  return r;
}

std::vector<uint32_t> visited(const SpatialHash& h, Vec2 c, double r) {
  std::vector<uint32_t> out;
  h.query_items(c, r, [&](const SpatialHash::Item& it) { out.push_back(it.index); });
  return out;
}

SpatialHash made(SpatialHash::Storage storage, const Robots& r) {
  SpatialHash h;
  h.set_storage(storage);
  h.reset({-15, -15}, {15, 15}, 0.7);
  h.build(r.centres, r.radii, r.flags);
  return h;
}

TEST(SpatialHash, SparseAndDenseHoldTheRobotsInTheSameOrderAndAnswerEveryQueryAlike) {
  for (uint64_t seed : {1, 2, 3}) {
    const Robots robots = random_robots(300, seed);
    const SpatialHash dense = made(SpatialHash::Storage::Dense, robots);
    const SpatialHash sparse = made(SpatialHash::Storage::Sparse, robots);
    ASSERT_FALSE(dense.sparse());
    ASSERT_TRUE(sparse.sparse());
    ASSERT_EQ(dense.order().size(), sparse.order().size());
    for (size_t k = 0; k < dense.order().size(); ++k) {
      const SpatialHash::Item &a = dense.order()[k], &b = sparse.order()[k];
      ASSERT_EQ(a.index, b.index) << "place " << k << ", seed " << seed;
      EXPECT_EQ(a.flags, b.flags);
      EXPECT_EQ(a.x, b.x);
      EXPECT_EQ(a.y, b.y);
      EXPECT_EQ(a.r, b.r);
    }
    EXPECT_EQ(dense.max_radius(), sparse.max_radius());
    std::mt19937_64 rng(seed + 100);
    std::uniform_real_distribution<double> pos(-25, 25), rad(0, 4);
    size_t found = 0;
    for (int q = 0; q < 2000; ++q) {
      const Vec2 c{pos(rng), pos(rng)};
      const double r = rad(rng);
      const std::vector<uint32_t> a = visited(dense, c, r);
      ASSERT_EQ(a, visited(sparse, c, r)) << "query at " << c.x << ", " << c.y << " r " << r;
      ASSERT_EQ(dense.count_items(c, r), a.size());
      ASSERT_EQ(sparse.count_items(c, r), a.size());
      found += a.size();
    }
    EXPECT_GT(found, 2000u) << "the queries should find robots, or they compare nothing";
  }
}

TEST(SpatialHash, AGridOfFarMoreCellsThanRobotsIsSparseAndACrowdedOneDense) {
  const Robots few = random_robots(10, 4);
  // 43 x 43 cells for 10 robots: sparse; for 300: dense.
  EXPECT_TRUE(made(SpatialHash::Storage::Auto, few).sparse());
  EXPECT_FALSE(made(SpatialHash::Storage::Auto, random_robots(300, 4)).sparse());
}

TEST(SpatialHash, AnEmptySparseHashFindsNothing) {
  const SpatialHash h = made(SpatialHash::Storage::Sparse, Robots{});
  EXPECT_TRUE(h.order().empty());
  EXPECT_TRUE(visited(h, {0, 0}, 100).empty());
  EXPECT_EQ(h.count_items({0, 0}, 100), 0u);
}

}  // namespace
}  // namespace troupe::sim
