// Feature-based localization: the landmark_learner player learns the
// field's expectation table in the simulator; MCL with the Gaussian
// landmark model then finds a robot driving on the field from its noisy
// omni-vision detections and odometry, starting from no idea where it is.
#include <unistd.h>

#include <cmath>

#include "drivers/common_desktop/landmark_model.h"
#include "host-sim/robocup/api/fiducial_key.h"
#include "tests/robocup/landmark_fixture.h"

namespace troupe::robocup::test {
namespace {

// ctest runs each test in a process of its own, several at once: each
// learns into a file of its own.
const std::string kTable =
    TROUPE_BINARY_DIR "/tests/robocup/field_test." + std::to_string(getpid()) + ".landmarks";

/// Learns the table once for every test of this file.
class LandmarkMcl : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { learn_field_table(kTable); }
  static void TearDownTestSuite() { std::filesystem::remove(kTable); }
};

TEST_F(LandmarkMcl, TheLearnedTableHoldsTheFieldsLandmarks) {
  desktop::LandmarkTable table;
  std::string error;
  ASSERT_TRUE(table.load(kTable, error)) << error;
  EXPECT_EQ(table.landmarks(), 10u);  // 2 goals, 4 goal posts, 4 corner posts
  EXPECT_EQ(table.poses(), 41u * 25u * 8u);
  // From the centre spot facing +x, the yellow goal (goal 1) is 4.5 m
  // ahead; between grid nodes and headings the expectation follows.
  const desktop::LandmarkKey yellow_goal{wire::FiducialKind::Goal, 1};
  double x, y;
  ASSERT_TRUE(table.expected({0, 0, 0}, table.column(yellow_goal), x, y));
  EXPECT_NEAR(x, 4.5, 1e-3);
  EXPECT_NEAR(y, 0.0, 1e-3);
  ASSERT_TRUE(table.expected({0.1, -0.35, 0.3}, table.column(yellow_goal), x, y));
  const double c = std::cos(0.3), s = std::sin(0.3), dx = 4.5 - 0.1, dy = 0.35;
  EXPECT_NEAR(x, c * dx + s * dy, 1e-3);
  EXPECT_NEAR(y, -s * dx + c * dy, 1e-3);
  EXPECT_FALSE(table.expected({20, 0, 0}, 0, x, y));  // off the grid
  EXPECT_EQ(table.column({wire::FiducialKind::Generic, 7}), -1);
  EXPECT_EQ(table.column({wire::FiducialKind::Ball, 0}), -1);  // learned without the ball
  EXPECT_GE(table.column({wire::FiducialKind::Post, 7}), 0);   // the last corner post
}

TEST_F(LandmarkMcl, BadTablesAreRefusedWithFileAndLine) {
  desktop::LandmarkTable table;
  std::string error;
  EXPECT_FALSE(table.parse("troupe-landmarks 1\n", "t", error));
  EXPECT_EQ(error, "t:1: landmark table version 1, this build reads 2");
  EXPECT_FALSE(table.parse("troupe-landmarks 2\ngrid 0 0 0 2 2 1\n", "t", error));
  EXPECT_NE(error.find("t:2: grid"), std::string::npos) << error;
  EXPECT_FALSE(table.parse("troupe-landmarks 2\ngrid 0 0 1 2 2 1\nlandmarks 1 100\n", "t", error));
  EXPECT_EQ(error, "t:3: landmarks: '100' is not KIND:ID (kind: ball, goal, post, ...)");
  EXPECT_FALSE(table.parse("troupe-landmarks 2\ngrid 0 0 1 2 2 1\nlandmarks 1 pole:1\n", "t", error));
  EXPECT_NE(error.find("'pole:1' is not KIND:ID"), std::string::npos) << error;
  EXPECT_FALSE(table.parse("troupe-landmarks 2\ngrid 0 0 1 2 2 1\nlandmarks 1 goal:0\n1 2\n1 x\n", "t", error));
  EXPECT_EQ(error, "t:5: 'x' is not a number");
  EXPECT_FALSE(table.parse("troupe-landmarks 2\ngrid 0 0 1 2 2 1\nlandmarks 1 goal:0\n1 2\n", "t", error));
  EXPECT_NE(error.find("ends after 1 of 4 pose lines"), std::string::npos) << error;
  EXPECT_FALSE(table.load(kTable + ".missing", error));
  EXPECT_NE(error.find("cannot open"), std::string::npos) << error;
}

TEST_F(LandmarkMcl, GlobalLocalizationConvergesFromFeatures) {
  desktop::LandmarkTable table;
  std::string error;
  ASSERT_TRUE(table.load(kTable, error)) << error;

  // Driving a circle on the field.
  auto sim = make_sim(runner_world(), error);
  ASSERT_TRUE(sim) << error;
  ASSERT_TRUE(sim->problems().empty()) << sim->problems().front();
  sim->command(0, {0.6, 0, 0.4});

  // The free space: the field and its border.
  desktop::OccupancyGrid map(110, 70, 0.1, {-5.5, -3.5, 0}, desktop::CellState::Free);
  desktop::MclParams params;
  params.min_particles = 500;
  params.max_particles = 5000;
  params.global_particles = 20000;
  params.update_min_d = 0.05;
  params.update_min_a = 0.05;
  params.alpha_slow = 0;  // no recovery: the robot is not kidnapped
  desktop::ParticleFilter filter(map, params);
  desktop::Rng rng(42);
  filter.init_global(rng);
  desktop::LandmarkLikelihood likelihood(table, {});
  std::vector<desktop::LandmarkObservation> seen;

  double measured_s = -1;
  for (int cycle = 0; cycle < 2000; ++cycle) {
    sim->step();
    const SensorReading& odom = sim->readings(0)[0];
    const SensorReading& omni = sim->readings(0)[1];
    if (!omni.valid || omni.time_s <= measured_s) continue;
    measured_s = omni.time_s;
    seen.clear();
    for (const Detection& d : omni.detections) {
      if (auto key = fiducial_key(d.kind, d.id)) seen.push_back({{key->kind, key->id}, d.x, d.y});
    }
    likelihood.set(seen);
    filter.update({odom.odometry.x, odom.odometry.y, odom.odometry.a}, likelihood, rng);
  }
  ASSERT_GT(filter.updates(), 50u);
  const RobotInfo truth = sim->robot(0);
  const desktop::Pose2 best = filter.best();
  EXPECT_LT(std::hypot(best.x - truth.pose.x, best.y - truth.pose.y), 0.25)
      << "estimate " << best.x << ", " << best.y << " truth " << truth.pose.x << ", " << truth.pose.y;
  EXPECT_LT(std::abs(desktop::wrap_angle(best.a - truth.pose.a)), 0.1);
}

}  // namespace
}  // namespace troupe::robocup::test
