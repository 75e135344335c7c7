// The simulated camera's pixels against geometry computed by hand: which
// columns and rows a box of known height fills, occlusion, depth along the
// pixel's ray, the floor and sky, determinism, and the Stage keys.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "host-sim/sim/loader.h"
#include "host-sim/sim/world.h"
#include "tests/sim/camera_pixels.h"
#include "tests/sim/scenes.h"
#include "tests/sim/temp_dir.h"

namespace troupe::sim {
namespace {

using test::depth;
using test::pixel;
using test::render;

constexpr double kDeg = kPi / 180;
constexpr uint32_t kRed = 0xFF0000, kBlue = 0x0000FF;

// A camera level on a robot at the origin facing +x: 64 x 48 px, 60 x 45
// degrees, its optical centre 0.5 m above the floor.
CameraDesc test_camera() {
  CameraDesc c;
  c.width = 64;
  c.height = 48;
  c.hfov = 60 * kDeg;
  c.vfov = 45 * kDeg;
  c.near = 0.05;
  c.far = 8;
  c.z = 0.5;
  return c;
}

// A large room (walls beyond the camera's range) with a red box 1 m high
// whose near face is at x = 3, y from -0.5 to 0.5.
WorldDesc box_scene() {
  WorldDesc d = test::room(20, 20);
  StaticDesc box;
  box.name = "box";
  box.size = {0.4, 1.0};
  box.polygons = {test::box(3, -0.5, 3.4, 0.5)};
  box.look.color = kRed;
  box.look.height = 1.0;
  d.statics.push_back(box);
  RobotDesc r = test::robot("cam", {0, 0, 0});
  r.cameras.push_back(test_camera());
  d.robots.push_back(r);
  return d;
}

// The pinhole model written out independently of the renderer.
struct Pinhole {
  double fx, fy, cx, cy;
  explicit Pinhole(const CameraDesc& c)
      : fx(0.5 * c.width / std::tan(0.5 * c.hfov)),
        fy(0.5 * c.height / std::tan(0.5 * c.vfov)),
        cx(0.5 * c.width),
        cy(0.5 * c.height) {}
  // Image column (px, continuous) where a point at forward x, left y falls.
  double column(double x, double y) const { return cx - fx * y / x; }
  // Image row (px, continuous) where a point at forward distance x and
  // height z falls, for a camera at height zc.
  double row(double x, double z, double zc) const { return cy - fy * (z - zc) / x; }
};

TEST(Camera, ABoxFillsTheColumnsAndRowsItsGeometryGives) {
  World w(box_scene(), Random(1));
  const CameraView v = render(w);
  ASSERT_EQ(v.width, 64);
  ASSERT_EQ(v.height, 48);
  ASSERT_EQ(v.rgb.size(), 64u * 48u * 3u);
  const Pinhole p(test_camera());
  // Columns: the face spans y in [-0.5, 0.5] at x = 3; the left edge
  // (y = 0.5) is at the smaller column.
  const double left = p.column(3, 0.5), right = p.column(3, -0.5);
  const int mid = int(p.cy);
  for (int u = 0; u < v.width; ++u) {
    const double c = u + 0.5;
    if (c > left + 1 && c < right - 1) {
      EXPECT_EQ(pixel(v, u, mid), kRed) << "column " << u;
    } else if (c < left - 1 || c > right + 1) {
      EXPECT_NE(pixel(v, u, mid), kRed) << "column " << u;
    }
  }
  // Rows in the middle column: from the box's top (1 m) down to the floor.
  const int u = v.width / 2;
  const double top = p.row(3, 1.0, 0.5), bottom = p.row(3, 0.0, 0.5);
  for (int row = 0; row < v.height; ++row) {
    const double c = row + 0.5;
    if (c > top + 1 && c < bottom - 1) {
      EXPECT_EQ(pixel(v, u, row), kRed) << "row " << row;
    } else if (c < top - 1 || c > bottom + 1) {
      EXPECT_NE(pixel(v, u, row), kRed) << "row " << row;
    }
  }
}

TEST(Camera, DepthIsTheDistanceAlongEachPixelsRay) {
  World w(box_scene(), Random(1));
  const CameraView v = render(w);
  const Pinhole p(test_camera());
  const double res = 0.02;
  // On the box's face: horizontal distance 3 / cos(bearing), lengthened by
  // the pixel ray's slope.
  for (int u : {28, 32, 36}) {
    for (int row : {18, 24, 30}) {
      const double bearing = std::atan2(p.cx - (u + 0.5), p.fx);
      const double t = 3 / std::cos(bearing);
      const double k = p.fy / std::cos(bearing);
      const double slope = (p.cy - (row + 0.5)) / k;
      EXPECT_NEAR(depth(v, u, row), t * std::sqrt(1 + slope * slope), 2 * res) << u << "," << row;
    }
  }
  // The floor at the bottom row: the ray falls 0.5 m, reaching it at
  // horizontal distance 0.5 k / (row - cy).
  const int bottom = v.height - 1;
  const double t = 0.5 * p.fy / (bottom + 0.5 - p.cy);
  EXPECT_NEAR(depth(v, 32, bottom), std::hypot(t, 0.5), 1e-3);
  EXPECT_EQ(pixel(v, 32, bottom), 0x808080u);
  // The sky at the top row outside the box: nothing in range.
  EXPECT_TRUE(std::isinf(depth(v, 2, 0)));
}

TEST(Camera, ANearerRobotOccludesTheBoxAndTheBoxShowsAboveALowOne) {
  WorldDesc d = box_scene();
  RobotDesc tall = test::robot("tall", {1.5, 0, 0}, 0.4);  // near face at x = 1.3
  tall.look.color = kBlue;
  tall.look.height = 1.5;
  d.robots.push_back(tall);
  World w(d, Random(1));
  const CameraView v = render(w);
  const Pinhole p(test_camera());
  const int u = v.width / 2;
  EXPECT_EQ(pixel(v, u, int(p.cy)), kBlue);
  EXPECT_NEAR(depth(v, u, int(p.cy)), 1.3, 0.02);
  // Nothing red in the robot's columns: it covers the box from top to floor.
  for (int row = 0; row < v.height; ++row) EXPECT_NE(pixel(v, u, row), kRed) << row;

  // A robot lower than the camera: the box shows above it.
  d.robots[1].look.height = 0.2;
  World low(d, Random(1));
  const CameraView lv = render(low);
  const double robot_top = p.row(1.3, 0.2, 0.5), box_top = p.row(3, 1.0, 0.5);
  int red = 0, blue = 0;
  for (int row = 0; row < lv.height; ++row) {
    const double c = row + 0.5;
    if (c > box_top + 1 && c < robot_top - 1) red += pixel(lv, u, row) == kRed;
    if (c > robot_top + 1) blue += pixel(lv, u, row) == kBlue;
  }
  EXPECT_GT(red, 5);
  EXPECT_GT(blue, 5);
}

TEST(Camera, TheRobotCarryingItIsNotInItsImage) {
  WorldDesc d = box_scene();
  d.robots[0].look.color = kBlue;
  d.robots[0].look.height = 2;  // taller than the camera, around it
  World w(d, Random(1));
  const CameraView v = render(w);
  for (size_t i = 0; i < v.rgb.size(); i += 3) {
    ASSERT_FALSE(v.rgb[i] == 0 && v.rgb[i + 1] == 0 && v.rgb[i + 2] == 0xFF) << "pixel " << i / 3;
  }
}

TEST(Camera, NotComputedWhileNobodyWantsIt) {
  World w(box_scene(), Random(1));
  w.step();
  EXPECT_EQ(w.camera(0).step, UINT64_MAX);
  EXPECT_EQ(w.camera(0).width, 0);
  w.set_wanted({SensorKind::Camera, 0}, true);
  w.step();
  EXPECT_EQ(w.camera(0).step, 2u);
}

TEST(Camera, SameSeedAndWorldGiveTheSameBytes) {
  auto run = [](double heading) {
    WorldDesc d = box_scene();
    test::add_movers(d, 1.5);
    d.robots[0].pose.a = heading;
    return test::camera_bytes_after_steps(d);
  };
  const std::vector<uint8_t> a = run(0), b = run(0), c = run(0.2);
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);  // the comparison can fail: another view gives other bytes
}

TEST(Camera, SizeChangesTakeEffectAndBadSizesAreRefused) {
  World w(box_scene(), Random(1));
  EXPECT_FALSE(w.set_camera_size(0, 0, 10));
  EXPECT_FALSE(w.set_camera_size(0, 10, kMaxCameraSide + 1));
  ASSERT_TRUE(w.set_camera_size(0, 32, 24));
  const CameraView v = render(w);
  EXPECT_EQ(v.width, 32);
  EXPECT_EQ(v.height, 24);
  EXPECT_EQ(v.depth.size(), 32u * 24u);
}

TEST(Camera, StageKeysLoad) {
  troupe::test::TempDir dir;
  world::Diagnostics diags;
  WorldDesc d;
  ASSERT_TRUE(load_world_file(dir.write("c.world", R"(
resolution 0.02
position ( name "r0" size [0.4 0.4 0.3]
  camera ( pose [0.1 0 0 0] size [0.1 0.07 0.06] resolution [64 48] range [0.1 6] fov [60 45] pantilt [10 -5] ) )
position ( name "r1" size [0.4 0.4 0.3] camera ( ) )
)"),
                              d, diags))
      << diags.str();
  EXPECT_EQ(diags.str().find("camera"), std::string::npos) << diags.str();
  ASSERT_EQ(d.robots.size(), 2u);
  ASSERT_EQ(d.robots[0].cameras.size(), 1u);
  const CameraDesc& c = d.robots[0].cameras[0];
  EXPECT_EQ(c.width, 64);
  EXPECT_EQ(c.height, 48);
  EXPECT_DOUBLE_EQ(c.near, 0.1);
  EXPECT_DOUBLE_EQ(c.far, 6);
  EXPECT_NEAR(c.hfov, 60 * kDeg, 1e-12);
  EXPECT_NEAR(c.vfov, 45 * kDeg, 1e-12);
  EXPECT_NEAR(c.pose.a, 10 * kDeg, 1e-12);
  EXPECT_NEAR(c.tilt, -5 * kDeg, 1e-12);
  EXPECT_NEAR(c.pose.x, 0.1, 1e-12);
  EXPECT_NEAR(c.z, 0.3 + 0.03, 1e-12);  // on top of the robot
  // Stage's defaults, its camera's size included.
  ASSERT_EQ(d.robots[1].cameras.size(), 1u);
  const CameraDesc& s = d.robots[1].cameras[0];
  EXPECT_EQ(s.width, 32);
  EXPECT_EQ(s.height, 32);
  EXPECT_DOUBLE_EQ(s.near, 0.2);
  EXPECT_DOUBLE_EQ(s.far, 8);
  EXPECT_NEAR(s.hfov, 70 * kDeg, 1e-12);
  EXPECT_NEAR(s.vfov, 40 * kDeg, 1e-12);
  EXPECT_NEAR(s.z, 0.3 + 0.025, 1e-12);
}

TEST(Camera, BadStageValuesAreErrorsWithFileAndLine) {
  for (const char* bad : {"resolution [0 48]", "resolution [64.5 48]", "resolution [5000 48]", "range [2 1]",
                          "range [0 5]", "fov [0 45]", "fov [180 45]", "pantilt [0 90]"}) {
    std::string diags;
    EXPECT_TRUE(test::camera_keys_refused_at_their_line(bad, diags)) << bad << ": " << diags;
    EXPECT_NE(diags.find("camera"), std::string::npos) << bad << ": " << diags;
  }
}

TEST(Camera, TheExampleWorldLoadsWithoutWarningsAndSeesTheVisitor) {
  world::Diagnostics diags;
  auto w = World::load(std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/camera.world", 1, diags);
  ASSERT_TRUE(w) << diags.str();
  EXPECT_EQ(diags.str(), "");
  const CameraView v = render(*w, w->robot(0).cameras.first);
  ASSERT_EQ(v.width, 160);
  ASSERT_EQ(v.height, 120);
  // The blue visitor, 0.3 m high, stands straight ahead below the camera's
  // horizon (the camera is 0.325 m up): the middle column under the centre.
  EXPECT_EQ(pixel(v, 80, 70), kBlue);
  EXPECT_NEAR(depth(v, 80, 70), 2.7 * std::sqrt(1 + std::pow((60 - 70.5) / (60 / std::tan(22.5 * kDeg)), 2)),
              0.03);
}

}  // namespace
}  // namespace troupe::sim
