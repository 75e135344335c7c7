// The omnidirectional (isometric mirror) camera against the mapping written
// out here independently of the renderer: where a box at a known bearing
// and distance meets the floor, how high it shows in the outer ring, the
// depth of a floor pixel, painted floor marks, determinism, and its Stage
// keys with their errors.
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
constexpr uint32_t kRed = 0xFF0000, kFloor = 0x808080, kSky = 0xB4D2F0, kWhite = 0xFFFFFF;

// 160 x 160 px: the mirror's rim 80 px from the centre, the ground ring 64
// px, 4 m of floor across it; 0.5 m above the floor.
CameraDesc omni_camera() {
  CameraDesc c;
  c.projection = CameraProjection::Omni;
  c.width = c.height = 160;
  c.near = 0.05;
  c.far = 8;
  c.z = 0.5;
  c.mirror_range = 4;
  c.mirror_ground = 0.8;
  c.mirror_top = 30 * kDeg;
  return c;
}

// The isometric mapping: image radius r <= ground (px) sees the floor
// r / ground * range m away; beyond it the elevation grows linearly from
// the floor at `range` to `top` at the rim. Forward is up, left is left.
struct Isometric {
  double cx, cy, rim, ground, range, low, top;
  explicit Isometric(const CameraDesc& c)
      : cx(0.5 * c.width),
        cy(0.5 * c.height),
        rim(0.5 * c.width),
        ground(c.mirror_ground * rim),
        range(c.mirror_range),
        low(-std::atan(c.z / c.mirror_range)),
        top(c.mirror_top) {}
  double radius_of_floor(double d) const { return d / range * ground; }
  double radius_of_elevation(double e) const { return ground + (e - low) / (top - low) * (rim - ground); }
  // The pixel at `radius` px along `bearing` (rad left of forward).
  int u(double bearing, double radius) const { return int(std::floor(cx - radius * std::sin(bearing))); }
  int v(double bearing, double radius) const { return int(std::floor(cy - radius * std::cos(bearing))); }
};

// A red box 1 m high whose near face, 0.8 m wide, squarely faces the
// camera `dist` m away at `bearing` (rad), the camera's robot at the origin
// facing +x in a room whose walls are beyond the camera's range.
WorldDesc box_scene(double bearing, double dist) {
  WorldDesc d = test::room(20, 20);
  StaticDesc box;
  box.name = "box";
  box.pose = {(dist + 0.2) * std::cos(bearing), (dist + 0.2) * std::sin(bearing), bearing};
  box.size = {0.4, 0.8};
  box.polygons = {test::box(-0.2, -0.4, 0.2, 0.4)};
  box.look.color = kRed;
  box.look.height = 1.0;
  d.statics.push_back(box);
  RobotDesc r = test::robot("cam", {0, 0, 0});
  r.cameras.push_back(omni_camera());
  d.robots.push_back(r);
  return d;
}

TEST(OmniCamera, ABoxMeetsTheFloorAtTheRadiusOfItsDistanceAlongItsBearing) {
  for (double bearing : {0.0, 60 * kDeg, 150 * kDeg, -100 * kDeg}) {
    World w(box_scene(bearing, 2.0), Random(1));
    const CameraView v = render(w);
    ASSERT_EQ(v.width, 160);
    const Isometric m(omni_camera());
    const double edge = m.radius_of_floor(2.0);  // 32 px
    EXPECT_EQ(pixel(v, m.u(bearing, edge - 2), m.v(bearing, edge - 2)), kFloor) << bearing;
    EXPECT_EQ(pixel(v, m.u(bearing, edge + 2), m.v(bearing, edge + 2)), kRed) << bearing;
    // Nothing red the other way round.
    EXPECT_EQ(pixel(v, m.u(bearing + kPi, edge + 2), m.v(bearing + kPi, edge + 2)), kFloor) << bearing;
    // The floor pixel's depth: its ray meets the floor r / ground * range
    // away, 0.5 m below the camera.
    const double r = edge / 2, d = r / m.ground * m.range;
    const int u = m.u(bearing, r), row = m.v(bearing, r);
    const double rc = std::hypot(u + 0.5 - m.cx, row + 0.5 - m.cy);  // the pixel centre's radius
    EXPECT_NEAR(depth(v, u, row), std::hypot(rc / m.ground * m.range, 0.5), 1e-3) << d;
  }
}

TEST(OmniCamera, TheOuterRingShowsTheBoxUpToTheElevationOfItsTop) {
  const double bearing = 30 * kDeg;
  World w(box_scene(bearing, 2.0), Random(1));
  const CameraView v = render(w);
  const Isometric m(omni_camera());
  // The top edge (1 m, 0.5 m above the camera, 2 m away) is seen at
  // elevation atan(0.5 / 2); the sky above it (the walls are out of range).
  const double top = m.radius_of_elevation(std::atan(0.5 / 2.0));
  ASSERT_GT(top, m.ground + 3);
  EXPECT_EQ(pixel(v, m.u(bearing, top - 1.5), m.v(bearing, top - 1.5)), kRed);
  EXPECT_EQ(pixel(v, m.u(bearing, top + 1.5), m.v(bearing, top + 1.5)), kSky);
  // Level (elevation 0) rays hit the face 2 m away at the camera's height.
  const double level = m.radius_of_elevation(0);
  const int u = m.u(bearing, level), row = m.v(bearing, level);
  EXPECT_EQ(pixel(v, u, row), kRed);
  EXPECT_NEAR(depth(v, u, row), 2.0, 0.1);
  // Beyond the rim, in the corners: nothing.
  EXPECT_EQ(pixel(v, 0, 0), 0u);
  EXPECT_TRUE(std::isinf(depth(v, 0, 0)));
}

TEST(OmniCamera, ARobotAtAKnownBearingAndDistance) {
  WorldDesc d = box_scene(0, 2.0);
  d.statics.pop_back();
  RobotDesc other = test::robot("other", {-1.5 * std::sqrt(0.5), 1.5 * std::sqrt(0.5), 0}, 0.4);
  other.look.color = 0x00C000;
  other.look.height = 0.3;
  d.robots.push_back(other);
  World w(d, Random(1));
  const CameraView v = render(w);
  const Isometric m(omni_camera());
  // Its centre 1.5 m away at 135 degrees; a square 0.4 m wide: its nearest
  // face along that bearing is at 1.5 - 0.2 sqrt(2) (the corner).
  const double bearing = 135 * kDeg, corner = 1.5 - 0.2 * std::sqrt(2.0);
  const double edge = m.radius_of_floor(corner);
  EXPECT_EQ(pixel(v, m.u(bearing, edge - 2), m.v(bearing, edge - 2)), kFloor);
  EXPECT_EQ(pixel(v, m.u(bearing, edge + 2), m.v(bearing, edge + 2)), 0x00C000u);
  // Lower than the camera: the outer ring's level ray passes over it.
  const double level = m.radius_of_elevation(0);
  EXPECT_EQ(pixel(v, m.u(bearing, level), m.v(bearing, level)), kSky);
}

TEST(OmniCamera, PaintedFloorMarksShowWhereTheyLie) {
  WorldDesc d = box_scene(0, 2.0);
  d.statics.pop_back();
  d.floor.color = 0x208020;
  // A white stroke 0.1 m wide across the floor 1 m ahead (x = 1).
  d.floor.marks.push_back({{1, -5}, {1, 5}, 0, 0.1, kWhite});
  // A white circle of radius 1.5 m about the camera.
  d.floor.marks.push_back({{0, 0}, {0, 0}, 1.5, 0.1, kWhite});
  World w(d, Random(1));
  const CameraView v = render(w);
  const Isometric m(omni_camera());
  // Ahead (bearing 0) the stroke at 1 m; at 45 degrees it lies 1 / cos 45.
  EXPECT_EQ(pixel(v, m.u(0, m.radius_of_floor(1.0)), m.v(0, m.radius_of_floor(1.0))), kWhite);
  EXPECT_EQ(pixel(v, m.u(0, m.radius_of_floor(0.8)), m.v(0, m.radius_of_floor(0.8))), 0x208020u);
  const double diag = m.radius_of_floor(std::sqrt(2.0));
  EXPECT_EQ(pixel(v, m.u(kPi / 4, diag), m.v(kPi / 4, diag)), kWhite);
  // The circle all around, here behind and to the right.
  const double ring = m.radius_of_floor(1.5);
  EXPECT_EQ(pixel(v, m.u(-2.5, ring), m.v(-2.5, ring)), kWhite);
  EXPECT_EQ(pixel(v, m.u(-2.5, ring + 3), m.v(-2.5, ring + 3)), 0x208020u);
}

TEST(OmniCamera, SameSeedAndWorldGiveTheSameBytes) {
  auto run = [](double heading) {
    WorldDesc d = box_scene(0.5, 2.0);
    d.floor.marks.push_back({{1, -5}, {1, 5}, 0, 0.1, kWhite});
    test::add_movers(d, -1.5);
    d.robots[0].pose.a = heading;
    return test::camera_bytes_after_steps(d);
  };
  const std::vector<uint8_t> a = run(0), b = run(0), c = run(0.2);
  ASSERT_EQ(a.size(), 160u * 160u * 7u);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);  // the comparison can fail: another heading gives other bytes
}

TEST(OmniCamera, StageKeysLoad) {
  troupe::test::TempDir dir;
  world::Diagnostics diags;
  WorldDesc d;
  ASSERT_TRUE(load_world_file(dir.write("c.world", R"(
position ( name "r0" size [0.4 0.4 0.3]
  camera ( mirror "isometric" mirror_range 3 mirror_ground 0.7 mirror_top 20 ) )
position ( name "r1" size [0.4 0.4 0.3] camera ( mirror "isometric" resolution [100 80] ) )
position ( name "r2" size [0.4 0.4 0.3] camera ( ) )
)"),
                              d, diags))
      << diags.str();
  EXPECT_EQ(diags.str(), "");
  const CameraDesc& a = d.robots[0].cameras.at(0);
  EXPECT_EQ(a.projection, CameraProjection::Omni);
  EXPECT_EQ(a.width, kOmniDefaultSide);
  EXPECT_EQ(a.height, kOmniDefaultSide);
  EXPECT_DOUBLE_EQ(a.mirror_range, 3);
  EXPECT_DOUBLE_EQ(a.mirror_ground, 0.7);
  EXPECT_NEAR(a.mirror_top, 20 * kDeg, 1e-12);
  const CameraDesc& b = d.robots[1].cameras.at(0);
  EXPECT_EQ(b.projection, CameraProjection::Omni);
  EXPECT_EQ(b.width, 100);
  EXPECT_EQ(b.height, 80);
  EXPECT_DOUBLE_EQ(b.mirror_range, 4);
  EXPECT_EQ(d.robots[2].cameras.at(0).projection, CameraProjection::Pinhole);
}

TEST(OmniCamera, BadMirrorValuesAreErrorsWithFileAndLine) {
  for (const char* bad :
       {"mirror \"conic\"", "mirror \"isometric\" mirror_range 0", "mirror \"isometric\" mirror_ground 1.5",
        "mirror \"isometric\" mirror_ground 0", "mirror \"isometric\" mirror_top 90"}) {
    std::string diags;
    EXPECT_TRUE(test::camera_keys_refused_at_their_line(bad, diags)) << bad << ": " << diags;
    EXPECT_NE(diags.find("mirror"), std::string::npos) << bad << ": " << diags;
  }
  // A mirror key without a mirror is unknown to a pinhole camera.
  troupe::test::TempDir dir;
  world::Diagnostics diags;
  WorldDesc d;
  load_world_file(dir.write("c.world", "position ( name \"r0\"\n  camera ( mirror_range 3 ) )\n"), d, diags);
  EXPECT_NE(diags.str().find("mirror_range"), std::string::npos) << diags.str();
}

TEST(OmniCamera, TheExampleWorldLoadsWithoutWarningsAndSeesItsGoalsAndRobots) {
  world::Diagnostics diags;
  auto w = World::load(std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/omni.world", 1, diags);
  ASSERT_TRUE(w) << diags.str();
  EXPECT_EQ(diags.str(), "");
  const CameraDesc& c = w->camera_desc(w->robot(0).cameras.first);
  ASSERT_EQ(c.projection, CameraProjection::Omni);
  const CameraView v = render(*w, w->robot(0).cameras.first);
  ASSERT_EQ(v.width, 160);
  const Isometric m(c);
  // The camera is 0.6 + 0.1 m up. Level rays (elevation 0) meet the yellow
  // goal ahead (4.3 m) and the blue one behind; the 0.6 m robots are lower.
  const double level = m.radius_of_elevation(0);
  EXPECT_EQ(pixel(v, m.u(0, level), m.v(0, level)), 0xFFFF00u);
  EXPECT_EQ(pixel(v, m.u(kPi, level), m.v(kPi, level)), 0x0000FFu);
  // The opponent (magenta), its centre 2 m ahead and 1 m to the right: the
  // floor just beyond its near face is hidden by it.
  const double bearing = std::atan2(-1.0, 2.0), r = m.radius_of_floor(std::hypot(2.0, 1.0));
  EXPECT_EQ(pixel(v, m.u(bearing, r), m.v(bearing, r)), 0xFF00FFu);
}

}  // namespace
}  // namespace troupe::sim
