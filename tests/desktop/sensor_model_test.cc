// The likelihood-field model against likelihoods worked out by hand, and the
// distance transform against brute force.
#include <gtest/gtest.h>

#include <cmath>

#include "drivers/common_desktop/likelihood_field.h"
#include "drivers/common_desktop/particle_filter.h"

namespace troupe::desktop {
namespace {

// 20 x 20 cells of 0.1 m, origin (0, 0), one occupied cell at (10, 10)
// whose centre is (1.05, 1.05).
OccupancyGrid one_obstacle() {
  OccupancyGrid g(20, 20, 0.1, {0, 0, 0}, CellState::Free);
  g.set(10, 10, CellState::Occupied);
  return g;
}

LikelihoodFieldParams params() {
  LikelihoodFieldParams p;
  p.sigma_hit = 0.2;
  p.z_hit = 0.8;
  p.z_rand = 0.2;
  p.max_range = 10.0;
  p.max_distance = 1.0;
  return p;
}

TEST(SensorModel, LikelihoodsMatchHandComputedValues) {
  OccupancyGrid map = one_obstacle();
  LikelihoodField field(map, params());
  // On the obstacle: d = 0.
  //   0.8 * 1/(sqrt(2 pi) 0.2) + 0.2/10 = 0.8 * 1.99471140 + 0.02 = 1.61576912
  EXPECT_NEAR(field.likelihood(1.05, 1.05), 1.61576912, 1e-5);
  // Three cells to the right: d = 0.3 m.
  //   0.8 * 1.99471140 * exp(-0.09 / 0.08) + 0.02 = 0.8 * 1.99471140 * 0.32465247 + 0.02 = 0.53807064
  EXPECT_NEAR(field.likelihood(1.35, 1.05), 0.53807064, 1e-5);
  // Diagonal (3, 4) cells away: d = 0.5 m.
  //   0.8 * 1.99471140 * exp(-0.25 / 0.08) + 0.02 = 0.8 * 1.99471140 * 0.04393693 + 0.02 = 0.09011320
  EXPECT_NEAR(field.likelihood(1.35, 1.45), 0.09011320, 1e-5);
  // Beyond max_distance (1 m) and off the map: capped at 1 m.
  //   0.8 * 1.99471140 * exp(-1 / 0.08) + 0.02 = 0.02000595
  EXPECT_NEAR(field.likelihood(1.05 + 1.5, 1.05 - 0.1), 0.02000595, 1e-7);
  EXPECT_NEAR(field.likelihood(-5, -5), 0.02000595, 1e-7);
  EXPECT_NEAR(field.distance(13, 14), 0.5, 1e-6);
  // Anywhere inside a cell reads that cell.
  EXPECT_EQ(field.log_likelihood(1.301, 1.001), field.log_likelihood(1.399, 1.099));
}

TEST(SensorModel, ScanLikelihoodIsTheSumOverUsedBeams) {
  OccupancyGrid map = one_obstacle();
  MclParams p;
  p.sensor = params();
  p.laser_max_range = 5.0;
  p.max_beams = 60;
  ParticleFilter filter(map, p);
  // Robot at (0.55, 1.05) facing +x: three beams at -90, 0, +90 degrees.
  // The forward beam reads 0.5 m and ends on the obstacle (d = 0). The side
  // beams read 0.3 m and end in cells (5, 7) and (5, 13), 5 cells across and
  // 3 cells up or down from the obstacle's cell (10, 10):
  // d = sqrt(34) * 0.1 = 0.58310 m.
  std::vector<float> ranges = {0.3f, 0.5f, 0.3f};
  ScanView scan{-kPi / 2, kPi / 2, 10.0, ranges};
  double d_side = std::sqrt(34.0) * 0.1;
  double g = 1.0 / (std::sqrt(2 * kPi) * 0.2);
  double on = std::log(0.8 * g + 0.02);
  double side = std::log(0.8 * g * std::exp(-d_side * d_side / 0.08) + 0.02);
  EXPECT_NEAR(filter.log_likelihood({0.55, 1.05, 0}, scan), on + 2 * side, 1e-5);
  // A beam at the laser's maximum, or beyond laser_max_range, is not used.
  std::vector<float> with_max = {0.3f, 0.5f, 10.0f};
  ScanView scan2{-kPi / 2, kPi / 2, 10.0, with_max};
  EXPECT_NEAR(filter.log_likelihood({0.55, 1.05, 0}, scan2), on + side, 1e-5);
  std::vector<float> with_far = {0.3f, 0.5f, 6.0f};
  ScanView scan3{-kPi / 2, kPi / 2, 10.0, with_far};
  EXPECT_NEAR(filter.log_likelihood({0.55, 1.05, 0}, scan3), on + side, 1e-5);
}

// The surface field: distances to the boundary between occupied and free
// cells, from both sides, so a beam that ends half a cell short of a wall
// and one that ends half a cell inside it are equally likely. A wall four
// cells thick (columns 10 to 13) across a 20 x 20 map of 0.1 m cells.
TEST(SensorModel, SurfaceFieldMeasuresFromTheWallSurfaceOnBothSides) {
  OccupancyGrid map(20, 20, 0.1, {0, 0, 0}, CellState::Free);
  for (uint32_t r = 0; r < 20; ++r) {
    for (uint32_t c = 10; c <= 13; ++c) map.set(c, r, CellState::Occupied);
  }
  LikelihoodFieldParams p = params();
  p.surface = true;
  LikelihoodField field(map, p);
  EXPECT_NEAR(field.distance(9, 5), 0.05, 1e-6);   // free, next to the wall: half a cell
  EXPECT_NEAR(field.distance(10, 5), 0.05, 1e-6);  // the wall's surface cell: half a cell deep
  EXPECT_NEAR(field.distance(7, 5), 0.25, 1e-6);   // three cells out
  EXPECT_NEAR(field.distance(11, 5), 0.15, 1e-6);  // inside: 2 cells to free space at column 9
  EXPECT_NEAR(field.distance(12, 5), 0.15, 1e-6);  // and 2 cells to column 14
  EXPECT_EQ(field.log_likelihood(0.95, 0.55), field.log_likelihood(1.05, 0.55));
  // The classic field calls the whole wall a perfect hit.
  p.surface = false;
  LikelihoodField classic(map, p);
  EXPECT_NEAR(classic.distance(12, 5), 0.0, 1e-6);
  EXPECT_NEAR(classic.distance(9, 5), 0.1, 1e-6);
}

TEST(SensorModel, DistanceTransformIsExact) {
  // Random obstacles; compare with the nearest obstacle found by brute force.
  OccupancyGrid g(37, 23, 1.0, {}, CellState::Free);
  Rng rng(5);
  std::vector<std::pair<int, int>> sites;
  for (int i = 0; i < 12; ++i) {
    int c = int(uniform01(rng) * 37), r = int(uniform01(rng) * 23);
    g.set(uint32_t(c), uint32_t(r), CellState::Occupied);
    sites.emplace_back(c, r);
  }
  std::vector<float> d2 = squared_distance_transform(g, CellState::Occupied, 1000);
  for (int r = 0; r < 23; ++r) {
    for (int c = 0; c < 37; ++c) {
      double best = 1e18;
      for (auto [sc, sr] : sites) best = std::min(best, double((sc - c) * (sc - c) + (sr - r) * (sr - r)));
      EXPECT_EQ(d2[size_t(r) * 37 + size_t(c)], float(best)) << c << "," << r;
    }
  }
  // A map without obstacles is everywhere at the cap.
  OccupancyGrid empty(5, 5, 1.0, {}, CellState::Free);
  for (float v : squared_distance_transform(empty, CellState::Occupied, 3)) {
    EXPECT_EQ(v, 9.0f);
  }
}

TEST(SensorModel, KldBoundGrowsWithBins) {
  EXPECT_EQ(kld_bound(1, 0.05, 2.326), 1u);
  // Fox 2003: k = 2 bins, epsilon 0.05, z 2.326:
  //   (k-1)/(2 epsilon) (1 - 2/(9(k-1)) + sqrt(2/(9(k-1))) z)^3 = 10 * 1.8741^3 = 65.84
  EXPECT_EQ(kld_bound(2, 0.05, 2.326), 66u);
  EXPECT_LT(kld_bound(10, 0.05, 2.326), kld_bound(100, 0.05, 2.326));
  EXPECT_LT(kld_bound(100, 0.05, 2.326), kld_bound(100, 0.01, 2.326));
}

}  // namespace
}  // namespace troupe::desktop
