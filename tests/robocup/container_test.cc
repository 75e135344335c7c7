// The client's SensorContainer against a served RoboCup world: sensors by
// model, by interface, and features from whichever sensor provides them,
// pushed or pulled.
#include <cmath>
#include <numbers>

#include "tests/robocup/serve_fixture.h"
#include "examples/robocup/sensor_container.h"

namespace troupe::robocup::test {
namespace {

using client::Client;
using client::Pose2;
using examples::SensorContainer;
using wire::Interface;

constexpr double kPi = std::numbers::pi;

class ContainerTest : public ServedWorld {
 protected:
  void SetUp() override {
    ServedWorld::SetUp();
    client_ = std::make_unique<Client>("127.0.0.1", port());
    ASSERT_TRUE(client_->connect()) << client_->error();
    sim_ = std::make_unique<client::SimulationProxy>(*client_);
  }
  void TearDown() override {
    sim_.reset();
    client_.reset();
    ServedWorld::TearDown();
  }
  /// Runs one cycle (every sensor of the world measures each cycle) and
  /// waits until its data has arrived.
  void step() {
    ASSERT_TRUE(sim_->step(1));
    ASSERT_TRUE(client_->sync());
  }

  std::unique_ptr<Client> client_;
  std::unique_ptr<client::SimulationProxy> sim_;
};

TEST_F(ContainerTest, FindsSensorsByModelAndInterface) {
  SensorContainer robot(*client_);
  std::string error;
  ASSERT_TRUE(robot.add_robot("striker", error)) << error;
  EXPECT_EQ(robot.models(), (std::vector<std::string>{"odometry", "kicker", "omni", "front", "laser"}));
  EXPECT_NE(robot.get<client::FiducialProxy>("omni"), nullptr);
  EXPECT_EQ(robot.get<client::RangerProxy>("omni"), nullptr);  // wrong interface
  EXPECT_NE(robot.get<client::RangerProxy>("laser"), nullptr);
  EXPECT_EQ(robot.model("sonar"), nullptr);
  EXPECT_EQ(robot.of_type(Interface::Fiducial).size(), 2u);
  EXPECT_EQ(robot.of_type(Interface::Position2d).size(), 1u);

  SensorContainer nobody(*client_);
  EXPECT_FALSE(nobody.add_robot("nobody", error));
  EXPECT_NE(error.find("nobody"), std::string::npos) << error;
}

TEST_F(ContainerTest, BallFeaturesComeFromWhicheverSensorSeesIt) {
  SensorContainer robot(*client_);
  std::string error;
  ASSERT_TRUE(robot.add_robot("striker", error)) << error;
  EXPECT_FALSE(robot.feature("ballDistance"));  // nothing measured yet
  EXPECT_FALSE(robot.feature("noSuchFeature"));

  // Behind the robot only the omni camera sees the ball.
  ASSERT_TRUE(sim_->set_pose("ball", {-1.2f, 0.5f, 0}));
  step();
  auto distance = robot.feature("ballDistance");
  auto bearing = robot.feature("ballBearing");
  ASSERT_TRUE(distance && bearing);
  EXPECT_EQ(distance->model, "omni");
  EXPECT_NEAR(distance->value, std::hypot(1.2, 0.5), 1e-3);
  EXPECT_NEAR(bearing->value, std::atan2(0.5, -1.2), 1e-3);
  EXPECT_EQ(distance->time_us, sim_->sim_time_us());

  // A container holding only the front camera (mounted 0.2 m ahead of the
  // robot's centre) gives the same robot-frame feature from it.
  client::FiducialProxy front(*client_, 1, 0);
  SensorContainer camera_only(*client_);
  camera_only.add("front", front);
  ASSERT_TRUE(sim_->set_pose("ball", {1.5f, 0.3f, 0}));
  step();
  auto seen = camera_only.feature("ballDistance");
  ASSERT_TRUE(seen);
  EXPECT_EQ(seen->model, "front");
  EXPECT_NEAR(seen->value, std::hypot(1.5, 0.3), 1e-3);
  EXPECT_NEAR(robot.feature("ballDistance")->value, seen->value, 1e-3);
  // Behind the robot the camera alone has nothing to say.
  ASSERT_TRUE(sim_->set_pose("ball", {-1.2f, 0.5f, 0}));
  step();
  EXPECT_FALSE(camera_only.feature("ballDistance"));
}

TEST_F(ContainerTest, GoalFeaturesFollowTheTeam) {
  SensorContainer robot(*client_);
  std::string error;
  ASSERT_TRUE(robot.add_robot("striker", error)) << error;
  // Facing the blue goal (-x) from 1 m left of the centre spot, the
  // keeper out of the line of sight.
  ASSERT_TRUE(sim_->set_pose("striker", {0, 1, float(kPi)}));
  ASSERT_TRUE(sim_->set_pose("keeper", {0, -2, 0}));
  step();
  robot.set_team(examples::Team::Yellow);  // attacks the blue goal
  ASSERT_TRUE(robot.feature("goalDistance") && robot.feature("goalBearing"));
  EXPECT_NEAR(robot.feature("goalDistance")->value, std::hypot(4.5, 1.0), 1e-3);
  EXPECT_NEAR(robot.feature("goalBearing")->value, std::atan2(1.0, 4.5), 1e-3);  // to the left
  EXPECT_NEAR(robot.feature("ownGoalDistance")->value, std::hypot(4.5, 1.0), 1e-3);
  robot.set_team(examples::Team::Blue);
  EXPECT_NEAR(std::abs(robot.feature("goalBearing")->value), kPi - std::atan2(1.0, 4.5), 1e-3);
}

TEST_F(ContainerTest, ObstacleAndOdometryFeaturesComeFromOtherInterfaces) {
  SensorContainer robot(*client_);
  std::string error;
  ASSERT_TRUE(robot.add_robot("striker", error)) << error;
  // The keeper's 0.44 m box 1 m ahead: its near face 0.78 m away.
  ASSERT_TRUE(sim_->set_pose("keeper", {1, 0, 0}));
  ASSERT_TRUE(sim_->set_pose("ball", {-2, 2, 0}));
  step();
  auto obstacle = robot.feature("obstacleDistance");
  ASSERT_TRUE(obstacle);
  EXPECT_EQ(obstacle->model, "laser");
  EXPECT_NEAR(obstacle->value, 0.78, 0.01);
  // Ranges travel in millimetres: the 1-degree beams within 2 degrees of
  // straight ahead all read the face's 0.780 m.
  EXPECT_NEAR(robot.feature("obstacleBearing")->value, 0.0, 0.036);
  auto heading = robot.feature("odometryHeading");
  ASSERT_TRUE(heading);
  EXPECT_EQ(heading->model, "odometry");
  EXPECT_NEAR(heading->value, 0.0, 1e-6);
}

TEST_F(ContainerTest, PullModeUpdatesOnlyWhenAsked) {
  SensorContainer robot(*client_);
  std::string error;
  ASSERT_TRUE(robot.add_robot("striker", error, wire::Delivery::Pull)) << error;
  ASSERT_TRUE(sim_->set_pose("ball", {2, 0, 0}));
  step();
  step();
  // Opened for pulling: what was pushed at the Open is all there is.
  const uint64_t before = robot.model("omni")->time_us();
  EXPECT_LT(before, sim_->sim_time_us());
  ASSERT_TRUE(robot.update());
  EXPECT_EQ(robot.model("omni")->time_us(), sim_->sim_time_us());
  ASSERT_TRUE(robot.feature("ballDistance"));
  EXPECT_NEAR(robot.feature("ballDistance")->value, 2.0, 1e-3);
}

}  // namespace
}  // namespace troupe::robocup::test
