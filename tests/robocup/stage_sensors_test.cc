// RoboCup robots carrying the engine's Stage sensor models (a laser, an
// omni camera) in a match's world file: the engine computes them on the
// match's own world, so they see the barrier, the lines and the ball.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "host-sim/robocup/game/world_desc.h"
#include "host-sim/sim/static_map.h"
#include "host-sim/sim/world.h"
#include "tests/robocup/sim_fixture.h"
#include "tests/sim/camera_pixels.h"

namespace troupe::robocup {
namespace {

// Blue1 at (-2, 0) facing +y (90 degrees), a Stage laser along its heading
// and an omni camera on top; the ball at (1, 1.5).
std::string world_with(const std::string& sensors) {
  return "interval_sim 10\nrobocup_field ( length 9 width 5 )\n"
         "ball ( radius 0.11 pose [1 1.5 0 0] deceleration 0 )\nreferee ( enabled 0 )\n" +
         test::robot("blue1", "blue", -2, 0, kPi / 2, test::pioneer_block(sensors));
}

const std::string kSensors = R"(
  laser ( range_max 8 fov 0 samples 1 )
  camera ( mirror "isometric" resolution [160 160] range [0.05 8] mirror_range 4 mirror_ground 0.8 mirror_top 30 )
)";

TEST(StageSensors, ALaserOnARoboCupRobotReadsTheBarrierAcrossTheField) {
  std::string error;
  auto sim = test::make_sim(world_with(kSensors), error);
  ASSERT_TRUE(sim) << error;
  sim::World& engine = sim->engine();
  const sim::RobotInfo& blue1 = engine.robot(1);
  ASSERT_EQ(blue1.rangers.count, 1u);
  engine.set_wanted({sim::SensorKind::Ranger, blue1.rangers.first}, true);
  sim->step();
  const sim::RangerView scan = engine.ranger(blue1.rangers.first);
  EXPECT_EQ(scan.step, 1u);
  // The barrier's inner face: half the width plus the border, 3.5 m.
  EXPECT_NEAR(scan.ranges[0], 3.5, 0.03);
}

TEST(StageSensors, AnOmniCameraOnARoboCupRobotSeesTheLinesTheBallAndAGoal) {
  std::string error;
  auto sim = test::make_sim(world_with(kSensors), error);
  ASSERT_TRUE(sim) << error;
  sim::World& engine = sim->engine();
  const sim::RobotInfo& blue1 = engine.robot(1);
  ASSERT_EQ(blue1.cameras.count, 1u);
  // Stacked on the robot: its 0.6 m top plus half the camera's height.
  EXPECT_GT(engine.camera_desc(blue1.cameras.first).z, 0.6);
  engine.set_wanted({sim::SensorKind::Camera, blue1.cameras.first}, true);
  sim->step();
  const sim::CameraView v = engine.camera(blue1.cameras.first);
  ASSERT_EQ(v.width, 160);
  const FieldColors colors;
  size_t lines = 0, ball = 0, carpet = 0, goal = 0;
  for (size_t i = 0; i + 2 < v.rgb.size(); i += 3) {
    const uint32_t c = uint32_t(v.rgb[i]) << 16 | uint32_t(v.rgb[i + 1]) << 8 | v.rgb[i + 2];
    lines += c == colors.lines;
    ball += c == colors.ball;
    carpet += c == colors.carpet;
    goal += c == colors.blue_goal || c == colors.yellow_goal;
  }
  EXPECT_GT(carpet, lines);
  EXPECT_GT(lines, 50u);
  EXPECT_GT(ball, 3u);
  EXPECT_GT(goal, 10u);
  // Where the isometric mirror puts the floor (tests/sim/omni_camera_test.cc
  // has the mapping): d m away at d / 4 * 64 px from the centre, bearing b
  // (left of forward) at (80 - r sin b, 80 - r cos b). The halfway line
  // (x = 0) is 2 m to the robot's right; 2 m ahead is carpet...
  auto at = [](const sim::CameraView& view, double bearing, double d) {
    const double r = d / 4 * 64;
    return sim::test::pixel(view, int(std::floor(80 - r * std::sin(bearing))),
                            int(std::floor(80 - r * std::cos(bearing))));
  };
  EXPECT_EQ(at(v, -kPi / 2, 2), colors.lines);
  EXPECT_EQ(at(v, 0, 2), colors.carpet);
  // ... until the ball is put there.
  sim->place_ball({-2, 2}, {});
  sim->step();
  EXPECT_EQ(at(engine.camera(blue1.cameras.first), 0, 2), colors.ball);
}

// The field's barrier and goals are static rigid bodies: the physics stops
// robots at them, and the grid only shows them (obstacle_return 0). A
// fiducial finder must not see a landmark through them any more than a
// ranger's beam passes them.
TEST(StageSensors, AFiducialFinderDoesNotSeeALandmarkBehindAGoalWall) {
  WorldSpec spec;
  std::string error;
  ASSERT_TRUE(
      test::world_from_text("robocup_field ( length 9 width 5 )\nreferee ( enabled 0 )\n", spec, error))
      << error;
  sim::WorldDesc desc = world_desc(spec);
  // The blue goal's back wall stands at x = -(4.5 + 0.6 + 0.05 / 2) m; the
  // barrier beyond it at -(5.5 + its thickness / 2).
  auto robot = [](const std::string& name, double x, double y) {
    sim::RobotDesc r;
    r.name = name;
    r.pose = {x, y, 0};
    r.size = {0.2, 0.2};
    r.polygons = {{{-0.1, -0.1}, {0.1, -0.1}, {0.1, 0.1}, {-0.1, 0.1}}};
    return r;
  };
  sim::RobotDesc finder = robot("finder", -3, 0);
  sim::FiducialDesc eye;
  eye.range_max = 8;
  eye.fov = 2 * kPi;
  finder.fiducials.push_back(eye);
  desc.robots.push_back(finder);
  sim::RobotDesc hidden = robot("behind_goal", -5.3, 0);
  hidden.look.fiducial_id = 7;
  desc.robots.push_back(hidden);
  sim::RobotDesc open = robot("in_the_open", -4, 1.8);
  open.look.fiducial_id = 8;
  desc.robots.push_back(open);
  sim::World engine(desc, sim::Random(1));
  const sim::RobotInfo& info = engine.robot(engine.robot_count() - 3);
  ASSERT_EQ(info.name, "finder");
  ASSERT_EQ(info.fiducials.count, 1u);
  engine.set_wanted({sim::SensorKind::Fiducial, info.fiducials.first}, true);
  engine.step();
  const sim::FiducialView v = engine.fiducial(info.fiducials.first);
  ASSERT_EQ(v.step, 1u);
  ASSERT_EQ(v.readings.size(), 1u) << "the landmark behind the goal's back wall was seen through it";
  EXPECT_EQ(v.readings[0].id, 8);
  EXPECT_NEAR(v.readings[0].range, std::hypot(1.0, 1.8), 1e-9);
  // A ranger's beam along the same line stops at the wall, before the landmark.
  const float wall = engine.map().cast({-3, 0}, {-1, 0}, 8);
  EXPECT_LT(wall, 2.3f);
}

TEST(StageSensors, ABadSensorValueIsAnErrorWithFileAndLine) {
  std::string error;
  auto sim = test::make_sim(world_with("  camera ( resolution [0 10] )\n"), error);
  EXPECT_FALSE(sim);
  EXPECT_NE(error.find("camera resolution"), std::string::npos) << error;
  EXPECT_NE(error.find("test.world:"), std::string::npos) << error;
}

}  // namespace
}  // namespace troupe::robocup
