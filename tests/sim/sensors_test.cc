// Sensor geometry against ranges computed by hand on known maps (within one
// grid cell), the fast ray caster against the plain per-cell walk, and the
// detectors (robots in beams, fiducials, blobs, bumpers).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <vector>

#include "host-sim/sim/static_map.h"
#include "host-sim/sim/world.h"
#include "host-sim/world/png_image.h"
#include "tests/sim/scenes.h"
#include "tests/sim/temp_dir.h"

namespace troupe::sim {
namespace {

constexpr double kDeg = kPi / 180;

RangerView scan(World& w, RobotId r, uint32_t k = 0) {
  const uint32_t index = w.robot(r).rangers.first + k;
  w.set_wanted({SensorKind::Ranger, index}, true);
  w.refresh_sensors();
  return w.ranger(index);
}

TEST(Ranger, LaserInARoomMatchesHandComputedRanges) {
  WorldDesc d = test::room(5, 3);
  RobotDesc r = test::robot("r0", {1, 0.5, 0});
  r.rangers.push_back(test::laser(181, kPi, 20));
  d.robots.push_back(r);
  World w(d, Random(1));
  RangerView v = scan(w, 0);
  ASSERT_EQ(v.ranges.size(), 181u);
  const double res = d.resolution;
  // Beam i points at -90 + i degrees.
  EXPECT_NEAR(v.ranges[90], 4.0, res);                                          // ahead: wall x = 5
  EXPECT_NEAR(v.ranges[180], 2.5, res);                                         // left: wall y = 3
  EXPECT_NEAR(v.ranges[0], 3.5, res);                                           // right: wall y = -3
  EXPECT_NEAR(v.ranges[135], 2.5 / std::sin(45 * kDeg), res * std::sqrt(2.0));  // up-right
  EXPECT_NEAR(v.ranges[120], 4 / std::cos(30 * kDeg), res * 2);                 // 30 deg left: x = 5 first
  for (float i : v.intensities) EXPECT_FLOAT_EQ(i, 1.0f);
}

TEST(Ranger, TransducerPoseAndRobotHeadingAreApplied) {
  WorldDesc d = test::room(5, 3);
  RobotDesc r = test::robot("r0", {0, 0, 90 * kDeg});
  // A sonar 0.2 m ahead of the centre, and one on the left side facing left.
  RangerDesc sonar;
  TransducerDesc t;
  t.range_max = 10;
  t.pose = {0.2, 0, 0};
  sonar.transducers.push_back(t);
  t.pose = {0, 0.1, 90 * kDeg};
  sonar.transducers.push_back(t);
  r.rangers.push_back(sonar);
  d.robots.push_back(r);
  World w(d, Random(1));
  RangerView v = scan(w, 0);
  ASSERT_EQ(v.ranges.size(), 2u);
  EXPECT_NEAR(v.ranges[0], 3 - 0.2, d.resolution);  // facing +y: wall y = 3
  EXPECT_NEAR(v.ranges[1], 5 - 0.1, d.resolution);  // facing -x: wall x = -5
}

TEST(Ranger, RangeLimitsAndOtherRobots) {
  WorldDesc d = test::room(5, 3);
  RobotDesc r = test::robot("r0", {-1, 0, 0});
  r.rangers.push_back(test::laser(3, 60 * kDeg, 2.5));
  r.rangers.edit_back().transducers[0].range_min = 0.5;
  d.robots.push_back(r);
  RobotDesc other = test::robot("r1", {1.5, 0, 0.3}, 0.4);
  other.look.ranger_return = 0.25;
  d.robots.push_back(other);
  d.robots.push_back(test::robot("ghost", {-1, 1.5, 0}, 0.4));
  d.robots.back().look.ranger_return = -1;  // invisible to rangers
  World w(d, Random(1));
  RangerView v = scan(w, 0);
  // The middle beam hits r1's outline (rotated 0.3 rad: its near face is
  // not axis aligned, so compute where the ray meets it).
  const double c = std::cos(0.3), s = std::sin(0.3);
  // Face x' = -0.2 in r1's frame: points 1.5 + (-0.2 c - y' s), with y = 0.
  const double yp = 0.2 * s / c;  // y' where the world y is 0 on that face
  const double hit_x = 1.5 + (-0.2 * c - yp * s);
  EXPECT_NEAR(v.ranges[1], hit_x - (-1), 1e-4);
  EXPECT_FLOAT_EQ(v.intensities[1], 0.25f);
  // Nothing within range on the outer beams: range_max.
  EXPECT_FLOAT_EQ(v.ranges[0], 2.5f);
  EXPECT_FLOAT_EQ(v.ranges[2], 2.5f);
  // Turned so its left beam points at the invisible robot: still nothing.
  w.set_pose(0, {-1, 0, 60 * kDeg});
  v = scan(w, 0);
  EXPECT_FLOAT_EQ(v.ranges[2], 2.5f);
  // Against a wall closer than range_min: reads range_min.
  w.set_pose(0, {4.7, 0, 0});
  v = scan(w, 0);
  EXPECT_FLOAT_EQ(v.ranges[1], 0.5f);
}

TEST(Ranger, BitmapFloorplanIsScaledAndFlipped) {
  troupe::test::TempDir dir;
  world::GrayImage img;
  img.width = 100;
  img.height = 50;
  img.pixels.assign(100 * 50, 255);
  for (int x = 0; x < 100; ++x) img.pixels[size_t(x)] = img.pixels[size_t(49 * 100 + x)] = 0;  // top, bottom
  for (int y = 0; y < 50; ++y) img.pixels[size_t(y * 100)] = img.pixels[size_t(y * 100 + 99)] = 0;
  for (int y = 0; y < 50; ++y) img.pixels[size_t(y * 100 + 80)] = 0;   // a wall at column 80
  for (int x = 30; x < 70; ++x) img.pixels[size_t(10 * 100 + x)] = 0;  // a shelf at row 10
  std::string err;
  ASSERT_TRUE(world::write_png(dir.path("map.png"), img, err)) << err;
  dir.write("w.world", R"(
resolution 0.02
define floorplan model ( color "gray30" boundary 1 obstacle_return 1 )
floorplan ( size [10 5 1] pose [0 0 0 0] bitmap "map.png" )
position ( name "r0" pose [-2 0 0 0] size [0.2 0.2]
  ranger ( sensor ( range [0 20] fov 0 samples 1 ) sensor ( pose [0 0 0 90] range [0 20] samples 1 ) ) )
)");
  world::Diagnostics diags;
  auto w = World::load(dir.path("w.world"), 1, diags);
  ASSERT_TRUE(w) << diags.str();
  EXPECT_EQ(diags.items().size(), 0u) << diags.str();
  RangerView v = scan(*w, 0);
  // 0.1 m per pixel, image centred: column 80 starts at x = 3; the robot is
  // at x = -2. Row 10 (from the top) spans y = 1.4 .. 1.5.
  EXPECT_NEAR(v.ranges[0], 5.0, 0.02);
  w->set_pose(0, {0, 0, 0});
  v = scan(*w, 0);
  EXPECT_NEAR(v.ranges[1], 1.4, 0.02);
}

TEST(Ranger, NoiseIsSeededAndOnlyOnReturns) {
  WorldDesc d = test::room(5, 3);
  RobotDesc r = test::robot("r0", {1, 0, 0});
  r.rangers.push_back(test::laser(90, kPi / 2, 4.5));
  r.rangers.edit_back().transducers[0].noise_variance = 0.01;  // sd 0.1 m
  d.robots.push_back(r);
  World a(d, Random(7)), b(d, Random(7)), c(d, Random(8));
  RangerView va = scan(a, 0), vb = scan(b, 0), vc = scan(c, 0);
  int differ = 0, at_max = 0;
  double sum = 0, sum2 = 0;
  int returns = 0;
  for (size_t i = 0; i < va.ranges.size(); ++i) {
    EXPECT_EQ(va.ranges[i], vb.ranges[i]);
    differ += va.ranges[i] != vc.ranges[i];
    if (va.ranges[i] >= 4.5f) ++at_max;
  }
  // Beams between about 27 and 42 degrees off the axis see nothing within
  // 4.5 m: they stay at range_max, without noise.
  EXPECT_GT(at_max, 0);
  EXPECT_GT(differ, 40);
  // Against the same world without noise: the errors have sd 0.1 m, mean 0.
  d.robots[0].rangers.edit(0).transducers[0].noise_variance = 0;
  World noiseless(d, Random(7));
  RangerView vn = scan(noiseless, 0);
  for (size_t i = 0; i < va.ranges.size(); ++i) {
    if (vn.ranges[i] >= 4.4f) continue;
    double e = va.ranges[i] - vn.ranges[i];
    sum += e;
    sum2 += e * e;
    ++returns;
  }
  ASSERT_GT(returns, 20);
  EXPECT_NEAR(std::sqrt(sum2 / returns), 0.1, 0.04);
  EXPECT_NEAR(sum / returns, 0.0, 0.05);
}

TEST(StaticMap, MarchingFindsTheSameCellAsThePerCellWalk) {
  std::string path = std::string(TROUPE_SHARED_DATA) + "/stage/simple.world";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "no Stage test data at " << path;
  world::Diagnostics diags;
  auto w = World::load(path, 1, diags);
  ASSERT_TRUE(w) << diags.str();
  // simple.world's map is small enough to be read without the coarse
  // level; a copy reads it first, as a large map would.
  StaticMap coarse = w->map();
  ASSERT_FALSE(coarse.coarse());
  coarse.set_coarse(true);
  for (const StaticMap* map : {&w->map(), static_cast<const StaticMap*>(&coarse)}) {
    SCOPED_TRACE(map->coarse() ? "coarse level" : "map only");
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> pos(-8.5, 8.5), ang(-kPi, kPi), range(0.1, 12);
    int exact = 0;
    const int n = 20000;
    std::vector<RayQuery> batch;
    std::vector<float> slow;
    for (int i = 0; i < n; ++i) {
      Vec2 o{pos(rng), pos(rng)};
      double a = ang(rng);
      Vec2 dir{std::cos(a), std::sin(a)};
      float maxr = float(range(rng));
      float fast = map->cast(o, dir, maxr);
      slow.push_back(map->cast_per_cell(o, dir, maxr));
      batch.push_back({o, dir, maxr});
      // Both report where the ray enters the same cell; only float rounding
      // of the restarted walk may differ (a ray through a cell corner).
      ASSERT_NEAR(fast, slow.back(), map->resolution()) << "ray " << i;
      exact += std::fabs(fast - slow.back()) < 1e-4;
    }
    EXPECT_GE(exact, n - n / 1000);
    // All at once, as a laser casts them: the same within a cell.
    std::vector<float> out(batch.size());
    map->cast_batch(batch, StaticMap::kRangerMask, out.data());
    for (int i = 0; i < n; ++i)
      ASSERT_NEAR(out[size_t(i)], slow[size_t(i)], map->resolution()) << "ray " << i;
  }
}

TEST(StaticMap, LargeMapsReadTheCoarseLevelAndGetTheSameAnswers) {
  // 2,200 x 2,200 cells (4.8 M): large enough for the coarse level. Boxes
  // of seeded sizes and places, a few cells to a few hundred.
  StaticMap map;
  map.reset({0, 0}, {22, 22}, 0.01);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> at(0, 22), size(0.02, 2.0);
  std::vector<std::pair<Vec2, Vec2>> boxes;
  for (int i = 0; i < 60; ++i) {
    const Vec2 lo{at(rng), at(rng)};
    const Vec2 hi{std::min(22.0, lo.x + size(rng)), std::min(22.0, lo.y + 0.1 * size(rng))};
    boxes.push_back({lo, hi});
    map.fill_box(lo, hi, true, true);
  }
  map.finish();
  ASSERT_TRUE(map.coarse());
  // Clearance stays a lower bound on the distance to every box, whether or
  // not the coarse level answers.
  for (int i = 0; i < 5000; ++i) {
    const Vec2 p{at(rng), at(rng)};
    double nearest = 1e300;
    for (const auto& [lo, hi] : boxes) {
      const double dx = std::max({lo.x - p.x, 0.0, p.x - hi.x}), dy = std::max({lo.y - p.y, 0.0, p.y - hi.y});
      nearest = std::min(nearest, std::hypot(dx, dy));
    }
    for (double enough : {0.0, 0.05, 0.5, 1e300}) {
      ASSERT_LE(map.clearance(p, enough), nearest + 1e-9) << "point " << i << " enough " << enough;
    }
  }
  // The same ranges as the per-cell walk, and as the map without its
  // coarse level.
  std::vector<RayQuery> rays;
  std::uniform_real_distribution<double> ang(-kPi, kPi), range(0.1, 12);
  for (int i = 0; i < 20000; ++i) {
    const double a = ang(rng);
    rays.push_back({{at(rng), at(rng)}, {std::cos(a), std::sin(a)}, float(range(rng))});
  }
  std::vector<float> coarse(rays.size()), fine(rays.size());
  map.cast_batch(rays, StaticMap::kRangerMask, coarse.data());
  map.set_coarse(false);
  map.cast_batch(rays, StaticMap::kRangerMask, fine.data());
  int exact = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const float slow = map.cast_per_cell(rays[i].origin, rays[i].dir, rays[i].max_range);
    ASSERT_NEAR(coarse[i], slow, map.resolution()) << "ray " << i;
    ASSERT_NEAR(coarse[i], fine[i], map.resolution()) << "ray " << i;
    exact += std::fabs(coarse[i] - slow) < 1e-4;
  }
  EXPECT_GE(exact, 20000 - 20);
}

TEST(Fiducial, SeesIdsInRangeAndFovButNotBehindWalls) {
  WorldDesc d = test::room(6, 3);
  d.statics[0].polygons.push_back(test::box(-0.05, 0.5, 0.05, 3.0));  // a wall from y = 0.5 up
  RobotDesc r = test::robot("finder", {-2, 1, 0});
  FiducialDesc f;
  f.range_max = 5;
  f.range_max_id = 3;
  f.fov = kPi;
  r.fiducials.push_back(f);
  d.robots.push_back(r);
  auto beacon = [](const char* name, Pose p, int id) {
    RobotDesc b = test::robot(name, p, 0.2);
    b.look.fiducial_id = id;
    return b;
  };
  d.robots.push_back(beacon("near", {-1.5, -0.5, 0.5}, 7));  // 1.58 m, to the right
  d.robots.push_back(beacon("far", {1.5, -1.5, 0}, 8));      // 4.3 m: seen, not identified
  d.robots.push_back(beacon("hidden", {2, 1.5, 0}, 9));      // behind the wall
  d.robots.push_back(beacon("behind", {-4, 1, 0}, 10));      // outside the fov
  World w(d, Random(1));
  const uint32_t index = w.robot(0).fiducials.first;
  w.set_wanted({SensorKind::Fiducial, index}, true);
  w.refresh_sensors();
  FiducialView v = w.fiducial(index);
  ASSERT_EQ(v.readings.size(), 2u);
  EXPECT_EQ(v.readings[0].id, 7);
  EXPECT_NEAR(v.readings[0].range, std::hypot(0.5, 1.5), 1e-9);
  EXPECT_NEAR(v.readings[0].bearing, std::atan2(-1.5, 0.5), 1e-9);
  EXPECT_NEAR(v.readings[0].pose.x, 0.5, 1e-9);
  EXPECT_NEAR(v.readings[0].pose.y, -1.5, 1e-9);
  EXPECT_NEAR(v.readings[0].pose.a, 0.5, 1e-9);
  EXPECT_EQ(v.readings[1].id, -1);
  EXPECT_NEAR(v.readings[1].range, std::hypot(3.5, 2.5), 1e-9);
}

TEST(Blobfinder, ARedRobotAheadIsABlobInTheMiddleColumns) {
  WorldDesc d = test::room(6, 3);
  d.statics[0].look.blob = false;  // walls give no blobs
  RobotDesc r = test::robot("eye", {0, 0, 0});
  BlobfinderDesc b;
  b.width = 80;
  b.height = 60;
  b.fov = 60 * kDeg;
  b.colors = {0xFF0000};
  r.blobfinders.push_back(b);
  d.robots.push_back(r);
  RobotDesc red = test::robot("red", {2, 0, 0}, 0.4);
  red.look.color = 0xFF0000;
  d.robots.push_back(red);
  RobotDesc blue = test::robot("blue", {2, 1.0, 0}, 0.4);
  blue.look.color = 0x0000FF;
  d.robots.push_back(blue);
  World w(d, Random(1));
  const uint32_t index = w.robot(0).blobfinders.first;
  w.set_wanted({SensorKind::Blobfinder, index}, true);
  w.refresh_sensors();
  BlobView v = w.blobfinder(index);
  ASSERT_EQ(v.blobs.size(), 1u);
  const Blob& blob = v.blobs[0];
  EXPECT_EQ(blob.color, 0xFF0000u);
  // Half-width atan(0.2 / 1.8) = 6.34 deg of 60 over 80 px: about 8.5 px
  // each side of the centre column.
  EXPECT_NEAR(0.5 * (blob.left + blob.right), 39.5, 1.0);
  EXPECT_NEAR(blob.right - blob.left + 1, 2 * 6.34 / 0.75, 2.0);
  EXPECT_NEAR(blob.range, 1.8, 0.02);
  EXPECT_LT(blob.top, blob.bottom);
}

}  // namespace
}  // namespace troupe::sim
