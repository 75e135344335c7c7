// From world files to worlds: simple.world as Stage reads it, units
// converted once, unknown keys as warnings with file:line, bad values and
// missing bitmaps as errors, and mutated files never crashing the engine.
#include "host-sim/sim/loader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "host-sim/sim/static_map.h"
#include "host-sim/sim/world.h"
#include "tests/sim/temp_dir.h"

namespace troupe::sim {
namespace {

constexpr double kDeg = kPi / 180;

std::string simple_world() {
  return std::string(TROUPE_SHARED_DATA) + "/stage/simple.world";
}

bool load_text(const std::string& text, WorldDesc& out, world::Diagnostics& d, troupe::test::TempDir& dir) {
  return load_world_file(dir.write("t.world", text), out, d);
}

TEST(Loader, SimpleWorldAsStageReadsIt) {
  if (!std::filesystem::exists(simple_world())) GTEST_SKIP() << "no Stage test data at " << simple_world();
  world::Diagnostics d;
  WorldDesc w;
  ASSERT_TRUE(load_world_file(simple_world(), w, d)) << d.str();
  EXPECT_EQ(d.items().size(), 0u) << d.str();
  EXPECT_DOUBLE_EQ(w.resolution, 0.02);
  EXPECT_DOUBLE_EQ(w.interval_sim, 0.1);
  EXPECT_DOUBLE_EQ(w.quit_time, 3600);
  EXPECT_LE(w.speedup, 0);  // as fast as possible
  EXPECT_EQ(w.window.width, 635);
  EXPECT_NEAR(w.window.scale, 36.995, 1e-9);

  ASSERT_EQ(w.statics.size(), 1u);
  const StaticDesc& cave = w.statics[0];
  EXPECT_EQ(cave.name, "cave");
  EXPECT_DOUBLE_EQ(cave.size.x, 16);
  ASSERT_TRUE(cave.bitmap);
  EXPECT_EQ(cave.bitmap->image->width, 500);
  EXPECT_TRUE(cave.boundary);
  EXPECT_FALSE(cave.look.obstacle);  // map.inc says obstacle_return 0
  EXPECT_DOUBLE_EQ(cave.look.ranger_return, 0.5);
  EXPECT_EQ(cave.look.color, 0x4D4D4Du);  // gray30

  ASSERT_EQ(w.robots.size(), 2u);
  const RobotDesc& r0 = w.robots[0];
  EXPECT_EQ(r0.name, "r0");
  EXPECT_DOUBLE_EQ(r0.pose.x, -6.946);
  EXPECT_NEAR(r0.pose.a, 45 * kDeg, 1e-12);
  EXPECT_EQ(r0.ctrl, "wander");
  EXPECT_EQ(r0.ctrl_loc.line, 53);
  EXPECT_EQ(r0.drive, Drive::Diff);
  EXPECT_DOUBLE_EQ(r0.velocity[0].max, 0.5);
  EXPECT_NEAR(r0.velocity[2].max, 90 * kDeg, 1e-12);
  EXPECT_NEAR(r0.acceleration[2].min, -90 * kDeg, 1e-12);
  EXPECT_TRUE(r0.has_localization_origin);
  EXPECT_EQ(r0.look.color, 0xFF0000u);
  EXPECT_EQ(r0.look.fiducial_id, 1);
  // Sonars (from pioneer2dx_base) are ranger 0, the laser ranger 1.
  ASSERT_EQ(r0.rangers.size(), 2u);
  ASSERT_EQ(r0.rangers[0].transducers.size(), 16u);
  EXPECT_NEAR(r0.rangers[0].transducers[0].pose.x, 0.075, 1e-12);
  EXPECT_NEAR(r0.rangers[0].transducers[0].pose.a, 90 * kDeg, 1e-12);
  EXPECT_NEAR(r0.rangers[0].transducers[0].fov, 15 * kDeg, 1e-12);
  EXPECT_DOUBLE_EQ(r0.rangers[0].transducers[0].range_max, 5.0);
  ASSERT_EQ(r0.rangers[1].transducers.size(), 1u);
  EXPECT_EQ(r0.rangers[1].transducers[0].samples, 180);
  EXPECT_NEAR(r0.rangers[1].transducers[0].fov, kPi, 1e-12);
  EXPECT_DOUBLE_EQ(r0.rangers[1].transducers[0].range_max, 8.0);
  // Body: the octagon scaled to 0.44 x 0.38 about the origin offset -0.04,
  // plus the laser's box (0.156 x 0.155 at the robot's centre).
  ASSERT_EQ(r0.polygons.size(), 2u);
  double xmin = 1e9, xmax = -1e9, ymin = 1e9, ymax = -1e9;
  for (Vec2 p : r0.polygons[0]) {
    xmin = std::min(xmin, p.x);
    xmax = std::max(xmax, p.x);
    ymin = std::min(ymin, p.y);
    ymax = std::max(ymax, p.y);
  }
  EXPECT_NEAR(xmin, -0.26, 1e-12);
  EXPECT_NEAR(xmax, 0.18, 1e-12);
  EXPECT_NEAR(ymax - ymin, 0.38, 1e-12);
  EXPECT_NEAR(r0.polygons[1][2].x - r0.polygons[1][0].x, 0.156, 1e-12);
}

TEST(Loader, SimpleWorldRasterizesTheCave) {
  if (!std::filesystem::exists(simple_world())) GTEST_SKIP() << "no Stage test data at " << simple_world();
  world::Diagnostics d;
  auto w = World::load(simple_world(), 1, d);
  ASSERT_TRUE(w) << d.str();
  const StaticMap& m = w->map();
  // 16 m at 0.02 m, plus the margin.
  EXPECT_NEAR(m.width() * m.resolution(), 16.08, 0.03);
  // cave.png's top-left corner pixel is dark (a wall); its centre is free.
  auto cell = [&](double x, double y) {
    return m.code(int((x - m.origin().x) / m.resolution()), int((y - m.origin().y) / m.resolution()));
  };
  EXPECT_EQ(cell(-7.99, 7.99), StaticMap::kVisible);  // seen by rangers, not an obstacle
  EXPECT_GT(cell(-6.9, -6.9), StaticMap::kBarrier);   // r0 starts in the open
}

TEST(Loader, UnitsAreConvertedOnce) {
  troupe::test::TempDir dir;
  world::Diagnostics d;
  WorldDesc w;
  ASSERT_TRUE(load_text(R"(unit_length "cm"
unit_angle "radians"
resolution 5
interval_sim 50
position ( pose [100 -200 0 1.5] size [40 30] velocity_bounds [-50 50 0 0 0 0 -2 2]
  ranger ( sensor ( range [10 500] fov 3 samples 7 ) ) )
)",
                        w, d, dir))
      << d.str();
  EXPECT_DOUBLE_EQ(w.resolution, 0.05);
  EXPECT_DOUBLE_EQ(w.interval_sim, 0.05);
  const RobotDesc& r = w.robots.at(0);
  EXPECT_DOUBLE_EQ(r.pose.x, 1.0);
  EXPECT_DOUBLE_EQ(r.pose.y, -2.0);
  EXPECT_DOUBLE_EQ(r.pose.a, 1.5);
  EXPECT_DOUBLE_EQ(r.size.x, 0.4);
  EXPECT_DOUBLE_EQ(r.velocity[0].max, 0.5);
  EXPECT_DOUBLE_EQ(r.velocity[2].max, 2);
  EXPECT_DOUBLE_EQ(r.rangers[0].transducers[0].range_min, 0.1);
  EXPECT_DOUBLE_EQ(r.rangers[0].transducers[0].range_max, 5.0);
  EXPECT_DOUBLE_EQ(r.rangers[0].transducers[0].fov, 3);
  EXPECT_EQ(r.name, "r0");  // unnamed robots are numbered
}

TEST(Loader, UnknownKeysAndTypesAreWarningsWithFileAndLine) {
  troupe::test::TempDir dir;
  world::Diagnostics d;
  WorldDesc w;
  ASSERT_TRUE(load_text(R"(resolution 0.1
bogus_world_key 3
position ( name "a" pose [0 0 0 0]
  wheels 4
  ranger ( sensor ( range [0 5] colour "red" ) )
  actuator ( pose [0.2 0 0 0] )
)
teleporter ( pose [3 3 0 0] )
position ( name "a" pose [1 1 0] )
)",
                        w, d, dir))
      << d.str();
  EXPECT_FALSE(d.has_errors());
  auto has = [&](int line, const std::string& text) {
    for (const auto& item : d.items()) {
      if (item.loc.line == line && item.message.find(text) != std::string::npos &&
          item.severity == world::Severity::Warning) {
        return true;
      }
    }
    return false;
  };
  EXPECT_TRUE(has(2, "unknown key 'bogus_world_key'")) << d.str();
  EXPECT_TRUE(has(4, "unknown key 'wheels' for model type 'position'")) << d.str();
  EXPECT_TRUE(has(5, "unknown key 'colour' for model type 'sensor'")) << d.str();
  EXPECT_TRUE(has(6, "'actuator' is not simulated")) << d.str();
  EXPECT_TRUE(has(8, "unknown model type 'teleporter'")) << d.str();
  EXPECT_TRUE(has(9, "already named 'a'")) << d.str();
  EXPECT_TRUE(has(9, "read as [x y angle]")) << d.str();
  EXPECT_EQ(w.robots.size(), 2u);
  EXPECT_NEAR(w.robots[1].pose.a, 0.0, 1e-12);
  EXPECT_EQ(w.statics.size(), 1u);  // the teleporter, as a plain model
}

TEST(Loader, RobotsOfOneMakeUpShareTheirRangersAndReadAsCopiesWould) {
  // One robot type, two instances, and a third robot writing the same
  // sensors out itself: all three hold one list of rangers, equal to what
  // each robot's own copy would be, and changing one robot's leaves the
  // others as they were.
  troupe::test::TempDir dir;
  world::Diagnostics d;
  WorldDesc w;
  ASSERT_TRUE(load_text(R"(define ring ranger ( sensor ( pose [0.1 0 0 0] range [0 2] fov 15 )
                     sensor ( pose [0 0.1 0 90] range [0 2] fov 15 ) )
define bot position ( size [0.2 0.2 0.1] ring ( ) )
bot ( name "a" pose [1 1 0 0] )
bot ( name "b" pose [2 2 0 0] )
position ( name "c" pose [3 3 0 0] size [0.2 0.2 0.1]
  ranger ( sensor ( pose [0.1 0 0 0] range [0 2] fov 15 ) sensor ( pose [0 0.1 0 90] range [0 2] fov 15 ) ) )
bot ( name "d" pose [4 4 0 0] ring ( ) )
)",
                        w, d, dir))
      << d.str();
  ASSERT_EQ(w.robots.size(), 4u);
  const RobotDesc &a = w.robots[0], &b = w.robots[1], &c = w.robots[2], &e = w.robots[3];
  EXPECT_TRUE(a.rangers.shares_with(b.rangers));
  EXPECT_TRUE(b.rangers.shares_with(c.rangers));
  ASSERT_EQ(c.rangers.size(), 1u);
  ASSERT_EQ(c.rangers[0].transducers.size(), 2u);
  EXPECT_NEAR(c.rangers[0].transducers[1].pose.a, 90 * kDeg, 1e-12);
  EXPECT_DOUBLE_EQ(c.rangers[0].transducers[1].range_max, 2);
  // A robot of another make-up (two rings) has its own.
  ASSERT_EQ(e.rangers.size(), 2u);
  EXPECT_FALSE(e.rangers.shares_with(a.rangers));
  EXPECT_EQ(e.rangers[1], a.rangers[0]);

  // The engine sees each robot's rangers as its own copy would give.
  World world(w, Random(1));
  uint32_t rangers = 0;
  for (RobotId r = 0; r < world.robot_count(); ++r) rangers += world.robot(r).rangers.count;
  EXPECT_EQ(rangers, 5u);
  EXPECT_DOUBLE_EQ(world.ranger_desc(world.robot(1).rangers.first).transducers[0].pose.x, 0.1);

  // Changing one robot's rangers gives it its own list.
  w.robots[1].rangers.edit(0).transducers[0].range_max = 5;
  EXPECT_DOUBLE_EQ(w.robots[1].rangers[0].transducers[0].range_max, 5);
  EXPECT_DOUBLE_EQ(w.robots[0].rangers[0].transducers[0].range_max, 2);
  EXPECT_DOUBLE_EQ(w.robots[2].rangers[0].transducers[0].range_max, 2);
  EXPECT_FALSE(w.robots[1].rangers.shares_with(w.robots[0].rangers));
  EXPECT_TRUE(w.robots[0].rangers.shares_with(w.robots[2].rangers));
}

TEST(Loader, AnUnknownKeyInARobotTypesSensorIsReportedForEveryRobotAsBefore) {
  // A define's sensor is one object shared by its robots; the unknown key
  // in it is still reported once per robot, at the define's line.
  troupe::test::TempDir dir;
  world::Diagnostics d;
  WorldDesc w;
  ASSERT_TRUE(load_text(R"(define bot position ( ranger ( sensor ( range [0 2] colour "red" ) ) )
bot ( name "a" )
bot ( name "b" )
bot ( name "c" )
)",
                        w, d, dir))
      << d.str();
  size_t reported = 0;
  for (const auto& item : d.items()) {
    if (item.message.find("unknown key 'colour' for model type 'sensor'") == std::string::npos) continue;
    ++reported;
    EXPECT_EQ(item.loc.line, 1);
  }
  EXPECT_EQ(reported, 3u) << d.str();
}

TEST(Loader, BadValuesAreErrorsWithFileAndLine) {
  struct Case {
    const char* text;
    int line;
    const char* message;
  };
  const Case cases[] = {
      {"resolution \"fine\"\n", 1, "needs a number"},
      {"\nresolution -1\n", 2, "resolution must be > 0"},
      {"interval_sim 0\n", 1, "interval_sim must be > 0"},
      {"position ( pose [0 \"x\" 0 0] )\n", 1, "needs numbers"},
      {"position (\n ranger ( sensor ( range [5 1] ) ) )\n", 2, "range min < max"},
      {"model ( bitmap \"missing.png\" size [1 1] )\n", 1, "cannot read bitmap \"missing.png\""},
      {"model ( size [0 1] )\n", 1, "size must be > 0"},
      {"resolution 0.0001\nmodel ( size [1000 1000] )\n", 1, "obstacle grid would need"},
      {"position ( pose [1e300 0 0 0] )\n", 1, "out of range"},
      {"model ( block ( points 3 point[0] [0 0] point[1] [1 0] ) )\n", 1, "no point[2]"},
      {"unit_length \"furlong\"\n", 1, "unit_length must be"},
      {"position ( blobfinder ( image [0 60] ) )\n", 1, "image must be"},
  };
  for (const Case& c : cases) {
    troupe::test::TempDir dir;
    world::Diagnostics d;
    WorldDesc w;
    EXPECT_FALSE(load_text(c.text, w, d, dir)) << c.text;
    bool found = false;
    for (const auto& item : d.items()) {
      if (item.severity == world::Severity::Error && item.loc.line == c.line &&
          item.message.find(c.message) != std::string::npos) {
        found = true;
        EXPECT_NE(item.loc.file->find("t.world"), std::string::npos);
      }
    }
    EXPECT_TRUE(found) << c.text << "\n" << d.str();
  }
}

// A campus-sized floorplan (Stage's large.world: 1,000 x 700 m at 0.02 m)
// is within what a sparse grid holds; four times its side is not, and the
// error says how many cells it would take and how many fit.
TEST(Loader, ACampusFitsAndAGridTooLargeEvenWhenSparseIsRefusedClearly) {
  troupe::test::TempDir dir;
  world::Diagnostics ok;
  WorldDesc campus;
  EXPECT_TRUE(load_text("resolution 0.02\nmodel ( size [1000 700] )\n", campus, ok, dir)) << ok.str();
  world::Diagnostics d;
  WorldDesc w;
  EXPECT_FALSE(load_text("\nresolution 0.02\nmodel ( size [4000 2800] )\n", w, d, dir));
  ASSERT_EQ(d.error_count(), 1u) << d.str();
  const auto& e = d.items().front();
  EXPECT_EQ(e.loc.line, 2);
  EXPECT_NE(e.message.find("the obstacle grid would need 59"), std::string::npos) << e.message;
  EXPECT_NE(e.message.find("more than even a sparse grid holds (4294967296)"), std::string::npos)
      << e.message;
  EXPECT_NE(e.message.find("use a coarser resolution"), std::string::npos) << e.message;
}

// Mutated copies of simple.world, loaded and stepped: every failure is a
// reported error, and whatever loads runs.
TEST(Loader, FuzzedSimpleWorldLoadsOrFailsCleanly) {
  if (!std::filesystem::exists(simple_world())) GTEST_SKIP() << "no Stage test data at " << simple_world();
  troupe::test::TempDir dir;
  const std::string base = std::filesystem::path(simple_world()).parent_path().string();
  for (const char* f : {"pioneer.inc", "map.inc", "sick.inc", "bitmaps/cave.png"}) {
    std::filesystem::create_directories(std::filesystem::path(dir.path(f)).parent_path());
    std::filesystem::copy_file(base + "/" + f, dir.path(f));
  }
  std::ifstream in(simple_world());
  const std::string original((std::istreambuf_iterator<char>(in)), {});
  std::mt19937_64 rng(77);
  const char* tokens[] = {"0",      "-1",    "1e6",      "\"x\"",  "[",     "]",      "(",
                          ")",      "99999", "0.000001", "#",      "\n",    "size",   "pose",
                          "bitmap", "ctrl",  "block",    "ranger", "[1 2]", "samples"};
  int loaded = 0, failed = 0;
  for (int round = 0; round < 120; ++round) {
    std::string text = original;
    for (int e = 0, n = 1 + int(rng() % 4); e < n; ++e) {
      size_t at = rng() % text.size();
      if (rng() % 2) {
        text.insert(at, std::string(" ") + tokens[rng() % std::size(tokens)] + " ");
      } else {
        text.erase(at, 1 + rng() % 12);
      }
    }
    world::Diagnostics d;
    std::unique_ptr<World> w;
    {
      WorldDesc desc;
      std::string path = dir.write("fuzz.world", text);
      if (load_world_file(path, desc, d)) w = std::make_unique<World>(desc, Random(round));
    }
    if (!w) {
      ++failed;
      ASSERT_TRUE(d.has_errors()) << text;
      continue;
    }
    ++loaded;
    for (RobotId i = 0; i < w->robot_count(); ++i) {
      const IndexRange r = w->robot(i).rangers;
      for (uint32_t k = r.first; k < r.first + r.count; ++k) w->set_wanted({SensorKind::Ranger, k}, true);
      w->command(i, Command::velocity(0.4, 0, 0.3));
    }
    for (int s = 0; s < 3; ++s) w->step();
  }
  EXPECT_GT(loaded, 10);
  EXPECT_GT(failed, 10);
}

}  // namespace
}  // namespace troupe::sim
