// RoboCup mode over the wire: a real TCP server (ServeLoop) and the C++
// client. Robots' devices, simulated time on the data, kicks, the game
// state, players started and stopped, and bad requests.
#include <cmath>

#include "runtime/clock.h"
#include "tests/robocup/serve_fixture.h"

namespace troupe::robocup::test {
namespace {

using client::Client;
using client::Pose2;

const wire::Fiducial* find(const client::FiducialProxy& p, wire::FiducialKind kind, int id) {
  for (size_t i = 0; i < p.fiducials().size(); ++i) {
    if (p.kind(i) == kind && p.fiducials()[i].id() == id) return &p.fiducials()[i];
  }
  return nullptr;
}

TEST_F(ServedWorld, ListsEachRobotsDevicesBySensorName) {
  Client c("127.0.0.1", port());
  ASSERT_TRUE(c.connect()) << c.error();
  std::vector<client::DeviceEntry> devices;
  ASSERT_TRUE(c.device_list(devices));
  std::vector<std::string> names;
  for (const auto& d : devices) names.push_back(d.text() + " " + d.driver);
  EXPECT_EQ(names, (std::vector<std::string>{
                       "striker/position2d:0 robocup/odometry", "striker/actuator:0 robocup/kicker",
                       "striker/fiducial:0 robocup/omni", "striker/fiducial:1 robocup/front",
                       "striker/ranger:0 robocup/laser", "keeper/position2d:0 robocup/base",
                       "keeper/actuator:0 robocup/kicker", "simulation:0 troupe-sim"}));
}

TEST_F(ServedWorld, DataCarriesTheSimulatedTimeOfItsMeasurement) {
  Client c("127.0.0.1", port());
  ASSERT_TRUE(c.connect()) << c.error();
  client::Position2dProxy base(c, 0, 0);
  client::FiducialProxy omni(c, 0, 0);
  client::SimulationProxy sim(c);
  ASSERT_TRUE(sim.step(10));
  ASSERT_TRUE(c.sync());
  EXPECT_EQ(sim.sim_time_us(), 100000u);
  EXPECT_EQ(sim.steps(), 10u);
  EXPECT_EQ(base.time_us(), 100000u);
  EXPECT_EQ(omni.time_us(), 100000u);
  // The ball 1 m ahead, seen by the omni camera on the robot's axis.
  const wire::Fiducial* ball = find(omni, wire::FiducialKind::Ball, 0);
  ASSERT_NE(ball, nullptr);
  EXPECT_NEAR(ball->x(), 1.0, 1e-3);
  EXPECT_NEAR(ball->y(), 0.0, 1e-3);
}

TEST_F(ServedWorld, TimeSyncLearnsTheSimulatorsClock) {
  {
    Client c("127.0.0.1", port());
    ASSERT_TRUE(c.connect()) << c.error();
    client::SimulationProxy sim(c);
    ASSERT_TRUE(sim.step(7));
  }
  // Paused, the simulator's clock stands at 70 ms: the offset puts the
  // middle of the TimeSync round trip there, and the round trip lies
  // within connect().
  const uint64_t before = monotonic_us();
  Client c("127.0.0.1", port());
  ASSERT_TRUE(c.connect()) << c.error();
  const uint64_t after = monotonic_us();
  const int64_t local_mid = 70000 - c.clock_offset_us();
  EXPECT_GE(local_mid, int64_t(before));
  EXPECT_LE(local_mid, int64_t(after));
}

TEST_F(ServedWorld, VelocityCommandsDriveARobotWithoutPlayer) {
  Client c("127.0.0.1", port());
  ASSERT_TRUE(c.connect()) << c.error();
  client::Position2dProxy base(c, 0, 0);
  client::SimulationProxy sim(c);
  ASSERT_TRUE(base.set_velocity(0.5f, 0, 0));
  ASSERT_TRUE(c.sync());  // the command reached the simulation
  ASSERT_TRUE(sim.step(100));
  ASSERT_TRUE(c.sync());
  Pose2 truth;
  ASSERT_TRUE(sim.get_pose("striker", truth));
  EXPECT_GT(truth.x, 0.3f);  // 1 s at up to 0.5 m/s after accelerating
  EXPECT_LT(truth.x, 0.5f);
  EXPECT_NEAR(truth.y, 0.0f, 0.01f);
  EXPECT_NEAR(base.x(), truth.x, 1e-3f);  // noise-free odometry
  EXPECT_NEAR(base.velocity().x, 0.5f, 1e-3f);
}

TEST_F(ServedWorld, TheKickerKicksTheBall) {
  Client c("127.0.0.1", port());
  ASSERT_TRUE(c.connect()) << c.error();
  client::ActuatorProxy kicker(c, 0, 0);
  client::SimulationProxy sim(c);
  ASSERT_TRUE(c.sync());
  EXPECT_EQ(kicker.mode(), wire::ActuatorMode::Ready);
  // The ball resting against the plate (front face at x = 0.25 m).
  ASSERT_TRUE(sim.set_pose("ball", {0.365f, 0, 0}, {0, 0, 0}));
  ASSERT_TRUE(kicker.kick());
  ASSERT_TRUE(c.sync());
  ASSERT_TRUE(sim.step(2));
  ASSERT_TRUE(c.sync());
  EXPECT_EQ(kicker.mode(), wire::ActuatorMode::Kicking);
  Pose2 ball, vel;
  ASSERT_TRUE(sim.get_pose("ball", ball, vel));
  EXPECT_GT(vel.x, 4.0f);  // 6 m/s from the plate, less the robot's recoil
  EXPECT_NEAR(vel.y, 0.0f, 0.05f);
  ASSERT_TRUE(sim.step(50));
  ASSERT_TRUE(c.sync());
  EXPECT_EQ(kicker.mode(), wire::ActuatorMode::Ready);
}

TEST_F(ServedWorld, AGoalShowsInTheGameState) {
  Client c("127.0.0.1", port());
  ASSERT_TRUE(c.connect()) << c.error();
  client::SimulationProxy sim(c);
  ASSERT_TRUE(c.sync());
  EXPECT_EQ(sim.game().score_blue + sim.game().score_yellow, 0u);
  // Into the yellow goal (+x): blue scores.
  ASSERT_TRUE(sim.set_pose("ball", {4.8f, 0, 0}));
  ASSERT_TRUE(sim.step(2));
  ASSERT_TRUE(c.sync());
  EXPECT_EQ(sim.game().score_blue, 1u);
  EXPECT_EQ(sim.game().score_yellow, 0u);
  EXPECT_EQ(sim.game().phase, wire::GamePhase::GoalPause);
  EXPECT_EQ(sim.game().last_event, "goal blue");
  client::GameState asked;
  ASSERT_TRUE(sim.get_game(asked));
  EXPECT_EQ(asked.score_blue, 1u);
  EXPECT_EQ(asked.events, sim.game().events);
  // After the pause the referee resets the field and play goes on.
  ASSERT_TRUE(sim.step(150));
  ASSERT_TRUE(c.sync());
  EXPECT_EQ(sim.game().phase, wire::GamePhase::Play);
  EXPECT_EQ(sim.game().score_blue, 1u);
}

TEST_F(ServedWorld, PlayersStartAndStopOverTheWire) {
  Client c("127.0.0.1", port());
  ASSERT_TRUE(c.connect()) << c.error();
  client::SimulationProxy sim(c);
  client::Position2dProxy keeper(c, 0, 1);
  EXPECT_FALSE(sim.start_player("keeper", "no_such_plugin"));
  EXPECT_NE(c.error().find("no_such_plugin"), std::string::npos) << c.error();
  EXPECT_FALSE(sim.start_player("keeper", "goalkeeper", {"policy=dance"}));
  EXPECT_NE(c.error().find("policy"), std::string::npos) << c.error();
  EXPECT_FALSE(sim.start_player("keeper", "goalkeeper", {"policy"}));
  EXPECT_NE(c.error().find("key=value"), std::string::npos) << c.error();
  EXPECT_FALSE(sim.start_player("nobody", "goalkeeper"));
  EXPECT_NE(c.error().find("nobody"), std::string::npos) << c.error();

  // A striker player on the keeper's robot goes for the ball at (1, 0).
  Pose2 start, moved;
  ASSERT_TRUE(sim.get_pose("keeper", start));
  ASSERT_TRUE(sim.start_player("keeper", "striker", {"drive=diff"}));
  ASSERT_TRUE(sim.step(100));
  ASSERT_TRUE(sim.get_pose("keeper", moved));
  EXPECT_GT(moved.x, start.x + 0.3f);
  // Stopped, the robot obeys its position2d again.
  ASSERT_TRUE(sim.stop_player("keeper"));
  ASSERT_TRUE(keeper.set_velocity(0, 0, 0));
  ASSERT_TRUE(c.sync());
  ASSERT_TRUE(sim.step(100));
  ASSERT_TRUE(sim.get_pose("keeper", start));
  ASSERT_TRUE(sim.step(50));
  ASSERT_TRUE(sim.get_pose("keeper", moved));
  EXPECT_NEAR(moved.x, start.x, 1e-3f);
  EXPECT_FALSE(sim.stop_player("nobody"));
}

TEST_F(ServedWorld, BadRequestsAreRefusedAndServingGoesOn) {
  Client c("127.0.0.1", port());
  ASSERT_TRUE(c.connect()) << c.error();
  client::SimulationProxy sim(c);
  client::Position2dProxy base(c, 0, 0);
  Pose2 pose;
  EXPECT_FALSE(sim.get_pose("nobody", pose));
  EXPECT_NE(c.error().find("no model named 'nobody'"), std::string::npos) << c.error();
  EXPECT_FALSE(sim.set_pose("ball", {NAN, 0, 0}));
  EXPECT_NE(c.error().find("finite"), std::string::npos) << c.error();
  EXPECT_FALSE(base.set_odometry(1, 2, 3));
  EXPECT_NE(c.error().find("odometry"), std::string::npos) << c.error();
  ASSERT_TRUE(sim.get_pose("ball", pose));
  EXPECT_NEAR(pose.x, 1.0f, 1e-4f);
}

TEST_F(ServedWorld, PullModeSendsDataOnlyWhenAsked) {
  Client pusher("127.0.0.1", port());
  ASSERT_TRUE(pusher.connect()) << pusher.error();
  client::SimulationProxy sim(pusher);
  Client puller("127.0.0.1", port());
  ASSERT_TRUE(puller.connect()) << puller.error();
  const wire::Address addr(0, uint16_t(wire::Interface::Position2d), 0);
  std::vector<uint64_t> times;
  puller.add_data_handler([&](const wire::Message& m) { times.push_back(wire::time_us(*m.header())); });
  ASSERT_TRUE(puller.open(addr, wire::Access::All, wire::Delivery::Pull));
  ASSERT_TRUE(sim.step(5));
  ASSERT_TRUE(puller.sync());  // anything pushed would have arrived by now
  EXPECT_TRUE(times.empty());
  ASSERT_TRUE(puller.pull(addr));
  ASSERT_EQ(times.size(), 1u);
  EXPECT_EQ(times[0], 50000u);
  ASSERT_TRUE(sim.step(3));
  ASSERT_TRUE(puller.pull(addr));
  ASSERT_EQ(times.size(), 2u);
  EXPECT_EQ(times[1], 80000u);
}

}  // namespace
}  // namespace troupe::robocup::test
