// Sensor plugins against known scenes: what a camera, the omni-vision,
// the laser (raw and iconic), the sonar and odometry report.
#include <gtest/gtest.h>

#include "sim_fixture.h"

namespace troupe::robocup {
namespace {

// A robot at the origin facing +x with one sensor, and a standing ball.
std::unique_ptr<Simulation> scene(const std::string& sensor, const std::string& more = "") {
  std::string error;
  auto sim = test::make_sim(
      "ball ( pose [2 0 0 0] deceleration 100 )\n" +
          test::robot("me", "blue", 0, 0, 0,
                      "  shape ( kind \"circle\" r 0.2 z [0 0.6] )\n  motion_plugin ( plugin \"diff_drive\" )\n  " +
                          sensor + "\n") +
          more,
      error);
  EXPECT_TRUE(sim) << error;
  if (sim) {
    EXPECT_TRUE(sim->problems().empty()) << sim->problems()[0];
  }
  return sim;
}

const Detection* find(const SensorReading& r, ObjectKind kind, int id = -2) {
  for (const Detection& d : r.detections) {
    if (d.kind == kind && (id == -2 || d.id == id)) return &d;
  }
  return nullptr;
}

TEST(Camera, SeesWhatIsInItsViewAndRangeOnly) {
  auto sim = scene("sensor_plugin ( plugin \"camera\" fov 1.0 range 5 z 0.5 )");
  sim->step();
  const SensorReading& r = sim->readings(0)[0];
  ASSERT_TRUE(r.valid);
  const Detection* ball = find(r, ObjectKind::Ball);
  ASSERT_NE(ball, nullptr);
  EXPECT_NEAR(ball->range(), 2, 1e-9);
  EXPECT_NEAR(ball->bearing(), 0, 1e-9);
  const Detection* goal = find(r, ObjectKind::Goal, 1);
  ASSERT_NE(goal, nullptr) << "the yellow goal, 4.5 m ahead";
  EXPECT_NEAR(goal->range(), 4.5, 1e-9);
  EXPECT_EQ(find(r, ObjectKind::Goal, 0), nullptr) << "the blue goal is behind";
  EXPECT_NE(find(r, ObjectKind::GoalPost, 2), nullptr);
  EXPECT_EQ(find(r, ObjectKind::Line), nullptr) << "lines are off unless asked for";
  // Out of the field of view, then out of range.
  sim->place_ball({0, 2}, {});
  sim->step();
  EXPECT_EQ(find(sim->readings(0)[0], ObjectKind::Ball), nullptr);
  sim->place_ball({3.0, 2.0}, {});
  sim->step();
  EXPECT_EQ(find(sim->readings(0)[0], ObjectKind::Ball), nullptr) << "bearing 0.59 rad is outside 0.5";
  sim->place_robot(0, {-1, 0, 0});
  sim->place_ball({4.3, 0}, {});
  sim->step();
  EXPECT_EQ(find(sim->readings(0)[0], ObjectKind::Ball), nullptr) << "5.3 m is beyond 5 m";
}

TEST(Camera, RobotsHideWhatIsBehindThem) {
  const std::string blocker =
      test::robot("wall", "yellow", 1, 0, 0, "  shape ( kind \"rect\" length 0.3 width 0.5 z [0 0.6] )\n");
  auto sim = scene("sensor_plugin ( plugin \"camera\" fov 1.0 range 5 z 0.5 )", blocker);
  sim->step();
  const SensorReading& r = sim->readings(0)[0];
  EXPECT_EQ(find(r, ObjectKind::Ball), nullptr);
  const Detection* other = find(r, ObjectKind::Robot, 1);
  ASSERT_NE(other, nullptr);
  EXPECT_EQ(other->team, int(Team::Yellow));
  EXPECT_NEAR(other->range(), 1, 1e-9);
  auto blind = scene("sensor_plugin ( plugin \"camera\" fov 1.0 range 5 z 0.5 occlusion 0 )", blocker);
  blind->step();
  EXPECT_NE(find(blind->readings(0)[0], ObjectKind::Ball), nullptr);
}

TEST(Camera, NoiseIsSeededAndRepeatable) {
  auto run = [](uint64_t seed) {
    auto sim = scene("sensor_plugin ( plugin \"camera\" fov 1.0 range 5 range_noise 0.05 bearing_noise 0.02 )",
                     "seed " + std::to_string(seed) + "\n");
    sim->step();
    return *find(sim->readings(0)[0], ObjectKind::Ball);
  };
  const Detection a = run(7), b = run(7), c = run(8);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  EXPECT_NE(a.x, c.x);
  EXPECT_NEAR(a.range(), 2, 0.5);
}

TEST(OmniVision, SeesLinesGoalsAndBallAllAround) {
  auto sim = scene("sensor_plugin ( plugin \"omnivision\" range 5 z 0.7 )");
  sim->place_robot(0, {1, 0.5, 0});
  sim->place_ball({0, -1}, {});
  sim->step();
  const SensorReading& r = sim->readings(0)[0];
  const Detection* ball = find(r, ObjectKind::Ball);
  ASSERT_NE(ball, nullptr) << "behind and to the side";
  EXPECT_NEAR(ball->x, -1, 1e-9);
  EXPECT_NEAR(ball->y, -1.5, 1e-9);
  const Detection* halfway = find(r, ObjectKind::Line, 4);
  ASSERT_NE(halfway, nullptr);
  EXPECT_NEAR(halfway->x, -1, 1e-9);
  EXPECT_NEAR(halfway->y, 0, 1e-9);
  EXPECT_NEAR(std::fabs(halfway->yaw), kPi / 2, 1e-9) << "the halfway line runs across the robot";
  const Detection* circle = find(r, ObjectKind::Line, -1);
  ASSERT_NE(circle, nullptr);
  EXPECT_NEAR(circle->range(), std::hypot(1, 0.5) - 1, 1e-9);
  EXPECT_NE(find(r, ObjectKind::Goal, 1), nullptr);
  EXPECT_EQ(find(r, ObjectKind::Goal, 0), nullptr) << "5.5 m away, beyond range";
  EXPECT_NE(find(r, ObjectKind::CornerPost, 0), nullptr);
}

TEST(Laser, RawBeamsMeasureWallsAndOnlyTallEnoughObjects) {
  // Three beams: right, ahead, left. The barrier is 1 m beyond the 2.5 m
  // touch lines; ahead, the beam passes the goal mouth to its back wall.
  auto sim = scene("sensor_plugin ( plugin \"laser\" beams 3 fov 3.14159265358979 range 8 z 0.3 )");
  sim->step();
  const SensorReading& r = sim->readings(0)[0];
  ASSERT_EQ(r.ranges.size(), 3u);
  EXPECT_NEAR(r.angle_min, -kPi / 2, 1e-9);
  EXPECT_NEAR(r.ranges[0], 3.5, 1e-5);
  EXPECT_NEAR(r.ranges[1], 5.1, 1e-5) << "the 0.22 m ball is under a 0.3 m beam";
  EXPECT_NEAR(r.ranges[2], 3.5, 1e-5);
  auto low = scene("sensor_plugin ( plugin \"laser\" beams 3 fov 3.14159265358979 range 8 z 0.1 )");
  low->step();
  EXPECT_NEAR(low->readings(0)[0].ranges[1], 2 - 0.11, 1e-5) << "a 0.1 m beam hits the ball";
}

TEST(Laser, IconicModeReportsObjectsItsBeamsReach) {
  auto sim = scene("sensor_plugin ( plugin \"laser\" mode \"iconic\" range 8 z 0.1 )",
                   test::robot("other", "yellow", 1, 1, 0, "  shape ( kind \"circle\" r 0.2 z [0 0.6] )\n"));
  sim->step();
  const SensorReading& r = sim->readings(0)[0];
  ASSERT_NE(find(r, ObjectKind::Ball), nullptr);
  const Detection* other = find(r, ObjectKind::Robot, 1);
  ASSERT_NE(other, nullptr);
  EXPECT_NEAR(other->range(), std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(other->bearing(), kPi / 4, 1e-9);
}

TEST(Ultrasonic, ReportsTheNearestObstacleInItsCone) {
  auto sim = scene("sensor_plugin ( plugin \"ultrasonic\" cone 0.6 range 3 z 0.1 )");
  sim->step();
  EXPECT_NEAR(sim->readings(0)[0].ranges.at(0), 2 - 0.11, 1e-6);
  sim->place_ball({0, 2}, {});
  sim->step();
  EXPECT_NEAR(sim->readings(0)[0].ranges.at(0), 3, 1e-6) << "nothing within 3 m ahead";
}

TEST(Odometry, FollowsTheRobotAndDriftsOnlyWithNoise) {
  auto drive = [](const std::string& sensor, uint64_t seed) {
    auto sim = scene(sensor, "seed " + std::to_string(seed) + "\n");
    sim->place_ball({0, -2}, {});
    for (int i = 0; i < 300; ++i) {
      sim->command(0, {1.0, 0, i < 150 ? 0.8 : -0.5});
      sim->step();
    }
    return std::make_pair(sim->readings(0)[0].odometry, sim->robot(0).pose);
  };
  auto [clean, truth] = drive("sensor_plugin ( plugin \"odometry\" )", 1);
  EXPECT_NEAR(clean.x, truth.x, 1e-9);
  EXPECT_NEAR(clean.y, truth.y, 1e-9);
  EXPECT_NEAR(clean.a, truth.a, 1e-9);
  const std::string noisy = "sensor_plugin ( plugin \"odometry\" translation_noise 0.05 rotation_noise 0.05 drift 0.05 )";
  auto [n1, t1] = drive(noisy, 1);
  auto [n2, t2] = drive(noisy, 1);
  auto [n3, t3] = drive(noisy, 2);
  EXPECT_EQ(n1, n2) << "the same seed drifts the same way";
  EXPECT_NE(n1, n3);
  EXPECT_GT(length(n1.position() - t1.position()), 1e-3) << "noise makes it drift";
  EXPECT_LT(length(n1.position() - t1.position()), 0.5) << "but not wildly over 3 m";
}

}  // namespace
}  // namespace troupe::robocup
