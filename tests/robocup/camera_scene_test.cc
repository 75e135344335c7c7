// A RoboCup field through the Stage engine's cameras: the centre line and
// centre circle where the pinhole model puts them, the goals in their
// colours at their bearings, the ball orange, another robot, all from a
// robot's known pose; the same world gives the same bytes.
#include "host-sim/robocup/game/camera_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "host-sim/sim/world.h"
#include "tests/robocup/sim_fixture.h"
#include "tests/sim/camera_pixels.h"

namespace troupe::robocup {
namespace {

using sim::test::pixel;
using sim::test::render;

constexpr double kDeg = kPi / 180;

// Blue1 stands at (-2, 0) facing the yellow goal; yellow1 2 m to its right.
const char* kWorld = R"(
include "robots/pioneer.inc"
interval_sim 10
seed 3
robocup_field ( length 9 width 5 )
ball ( radius 0.11 pose [1 1.5 0 0] )
referee ( enabled 0 )
pioneer ( name "blue1" team "blue" pose [-2 0 0 0] )
pioneer ( name "yellow1" team "yellow" pose [-2 -2 0 0] )
)";

sim::WorldDesc scene_with(const sim::CameraDesc& camera) {
  WorldSpec spec;
  std::string error;
  EXPECT_TRUE(test::world_from_text(kWorld, spec, error)) << error;
  sim::WorldDesc d = camera_scene(spec);
  EXPECT_EQ(d.robots.size(), 3u);  // the ball, blue1, yellow1
  // In place of the omni camera pioneer.inc gives it: camera 0 is this one.
  d.robots.at(1).cameras.assign(1, camera);
  return d;
}

TEST(CameraScene, ThePinholeCameraSeesTheLinesWhereTheGeometryPutsThemAndTheYellowGoal) {
  sim::CameraDesc c;
  c.width = 160;
  c.height = 120;
  c.hfov = 60 * kDeg;
  c.vfov = 45 * kDeg;
  c.near = 0.05;
  c.z = 0.5;
  sim::World w(scene_with(c), sim::Random(1));
  const sim::CameraView v = render(w);
  const FieldColors colors;
  // A level pinhole: the floor d m ahead is seen at y = cy + fy z / d.
  const double fy = 60 / std::tan(22.5 * kDeg), cy = 60;
  auto row_of = [&](double d) { return int(std::floor(cy + fy * 0.5 / d)); };
  EXPECT_EQ(pixel(v, 80, row_of(2.0)), colors.lines);   // the halfway line, x = 0
  EXPECT_EQ(pixel(v, 80, row_of(3.0)), colors.lines);   // the centre circle, x = 1
  EXPECT_EQ(pixel(v, 80, row_of(1.5)), colors.carpet);  // between them: carpet
  EXPECT_EQ(pixel(v, 80, row_of(2.5)), colors.carpet);
  // Through the yellow goal's mouth its back wall, 7.1 m ahead: 0.75 m up.
  EXPECT_EQ(pixel(v, 80, int(std::floor(cy - fy * 0.25 / 7.1))), colors.yellow_goal);
}

TEST(CameraScene, TheOmniCameraSeesGoalsBallAndRobotAtTheirBearings) {
  sim::CameraDesc c;
  c.projection = sim::CameraProjection::Omni;
  c.width = c.height = 160;
  c.near = 0.05;
  c.z = 0.5;
  c.mirror_range = 4;
  c.mirror_ground = 0.8;
  c.mirror_top = 30 * kDeg;
  sim::World w(scene_with(c), sim::Random(1));
  const sim::CameraView v = render(w);
  const FieldColors colors;
  // The isometric mapping (tests/sim/omni_camera_test.cc has it in full):
  // floor d m away at d / 4 * 64 px, level at 64 + (0 - low) / (top - low)
  // * 16 px; bearing b (left of forward) at (80 - r sin b, 80 - r cos b).
  const double low = -std::atan(0.5 / 4);
  auto at = [&](double bearing, double r) {
    return pixel(v, int(std::floor(80 - r * std::sin(bearing))), int(std::floor(80 - r * std::cos(bearing))));
  };
  auto floor_r = [](double d) { return d / 4 * 64; };
  // Behind: the blue goal line 2.5 m away, carpet before it, the goal's
  // back wall 3.1 m away.
  EXPECT_EQ(at(kPi, floor_r(2.5)), colors.lines);
  EXPECT_EQ(at(kPi, floor_r(2.0)), colors.carpet);
  EXPECT_EQ(at(kPi, floor_r(3.3)), colors.blue_goal);
  // Ahead, level: the yellow goal's back wall, 7.1 m away.
  EXPECT_EQ(at(0, 64 + (0 - low) / (30 * kDeg - low) * 16), colors.yellow_goal);
  // The ball: its centre 3.35 m away at atan2(1.5, 3).
  const double ball = std::hypot(3.0, 1.5);
  EXPECT_EQ(at(std::atan2(1.5, 3.0), floor_r(ball)), colors.ball);
  EXPECT_EQ(at(std::atan2(1.5, 3.0), floor_r(ball - 0.3)), colors.carpet);
  // Yellow1 to the right: its near side 2 - 0.19 m away.
  EXPECT_EQ(at(-kPi / 2, floor_r(1.9)), colors.robot);
  EXPECT_EQ(at(-kPi / 2, floor_r(1.6)), colors.carpet);

  // The same world and seed: the same bytes.
  sim::World again(scene_with(c), sim::Random(1));
  const sim::CameraView v2 = render(again);
  EXPECT_TRUE(std::equal(v.rgb.begin(), v.rgb.end(), v2.rgb.begin(), v2.rgb.end()));
}

TEST(CameraScene, ABadLineWidthIsAnErrorNamingTheKey) {
  WorldSpec spec;
  std::string error;
  EXPECT_FALSE(test::world_from_text("robocup_field ( line_width 3 )\n", spec, error));
  EXPECT_NE(error.find("line_width"), std::string::npos) << error;
}

}  // namespace
}  // namespace troupe::robocup
