// Headless snapshots: the map, robots in their colours and ranger beams land
// where the world says they are.
#include <gtest/gtest.h>

#include "host-sim/sim/snapshot.h"
#include "host-sim/sim/static_map.h"
#include "tests/sim/scenes.h"
#include "tests/sim/temp_dir.h"

namespace troupe::sim {
namespace {

uint32_t pixel(const world::RgbImage& img, int x, int y) {
  const uint8_t* p = &img.pixels[(size_t(y) * size_t(img.width) + size_t(x)) * 3];
  return (uint32_t(p[0]) << 16) | (uint32_t(p[1]) << 8) | p[2];
}

TEST(Snapshot, DrawsWallsRobotsAndBeams) {
  WorldDesc d = test::room(4, 2);
  RobotDesc r = test::robot("r0", {-2, 0, 0}, 0.6);
  r.look.color = 0x00FF00;
  r.rangers.push_back(test::laser(1, 0, 10));
  d.robots.push_back(r);
  World w(d, Random(1));
  w.set_wanted({SensorKind::Ranger, 0}, true);
  w.refresh_sensors();
  SnapshotOptions opt;
  opt.scale = 10;  // px/m
  world::RgbImage img = render(w, opt);
  // The map spans the walls (8.4 x 4.4 m) plus a margin: about 85 x 45 px.
  EXPECT_NEAR(img.width, 85, 2);
  EXPECT_NEAR(img.height, 45, 2);
  const Vec2 lo = w.map().origin();
  auto at = [&](double x, double y) {
    return pixel(img, int((x - lo.x) * 10), int(img.height - (y - lo.y) * 10));
  };
  EXPECT_EQ(at(-4.1, 0), 0x404040u);    // left wall
  EXPECT_EQ(at(-2.2, 0.2), 0x00FF00u);  // the robot's body
  EXPECT_EQ(at(1.0, 0.0), 0x70C070u);   // its beam, on the way to the right wall
  EXPECT_EQ(at(1.0, 1.0), 0xFFFFFFu);   // open floor
  troupe::test::TempDir dir;
  std::string err;
  ASSERT_TRUE(write_snapshot(w, dir.path("s.png"), err, opt)) << err;
  world::GrayImage back;
  ASSERT_TRUE(world::read_png(dir.path("s.png"), back, err)) << err;
  EXPECT_EQ(back.width, img.width);
  EXPECT_FALSE(write_snapshot(w, dir.path("no/such/dir/s.png"), err, opt));
  EXPECT_FALSE(err.empty());
}

}  // namespace
}  // namespace troupe::sim
