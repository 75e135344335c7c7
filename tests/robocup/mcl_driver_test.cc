// The mcl driver with landmark features, in one node with the RoboCup
// server: it uses the robot's odometry (position2d:0) and omni-vision
// detections (fiducial:0) as served, no map, and finds the robot on the
// field from global localization.
#include <unistd.h>

#include <cmath>
#include <fstream>

#include "host-sim/robocup/serve/robocup_server.h"
#include "runtime/node_config.h"
#include "tests/robocup/landmark_fixture.h"

namespace troupe::robocup::test {
namespace {

// ctest runs each test in a process of its own, several at once: every
// process writes and reads files of its own.
const std::string kDir = TROUPE_BINARY_DIR "/tests/robocup";
const std::string kTag = "/mcl_driver_test." + std::to_string(getpid());
const std::string kTable = kDir + kTag + ".landmarks";

// Keeps the newest pose a device publishes.
class PoseProbe final : public Driver {
 public:
  bool setup(Node&, const DriverSetup&, std::string&) override { return true; }
  void on_data(DeviceId, const wire::Message& data) override {
    const wire::Position2dState* s = data.body_as_Position2dState();
    if (s == nullptr || s->pose() == nullptr) return;
    x = s->pose()->x(), y = s->pose()->y(), a = s->pose()->a();
    ++samples;
  }
  double x = 0, y = 0, a = 0;
  size_t samples = 0;
};

std::string mcl_config(const std::string& table, const std::string& uses) {
  return R"({ "name": "robocup-mcl", "port": 0, "drivers": [
    { "driver_type": "mcl",
      "driver": { "landmark_table": ")" +
         table + R"(", "min_particles": 500, "max_particles": 5000, "global_particles": 20000,
                  "update_min_d": 0.05, "update_min_a": 0.05, "alpha_slow": 0, "seed": 4 },
      "uses": [)" +
         uses + R"(],
      "provides": ["localize:0", "position2d:5"] } ] })";
}

bool load(const std::string& json, LoadedConfig& cfg, std::string& error) {
  const std::string path = kDir + kTag + ".json";
  std::ofstream(path) << json;
  return load_config(path, cfg, error);
}

class MclDriver : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { learn_field_table(kTable); }
  static void TearDownTestSuite() {
    for (const char* end : {".landmarks", ".json", ".bad"}) std::filesystem::remove(kDir + kTag + end);
  }
  void SetUp() override {
    std::string error;
    sim_ = make_sim(runner_world(), error);
    ASSERT_TRUE(sim_) << error;
    node_ = std::make_unique<Node>(Node::Options{});
    auto server = std::make_unique<RobocupServer>(*sim_, control_);
    server_ = server.get();
    ASSERT_TRUE(node_->add_driver(std::move(server), DriverSetup{}, error)) << error;
  }

  sim::SimControl control_;
  std::unique_ptr<Simulation> sim_;
  std::unique_ptr<Node> node_;
  RobocupServer* server_ = nullptr;
};

TEST_F(MclDriver, LocalizesFromServedLandmarkFeatures) {
  LoadedConfig cfg;
  std::string error;
  ASSERT_TRUE(load(mcl_config(kTable, R"("position2d:0", "fiducial:0")"), cfg, error)) << error;
  ASSERT_TRUE(build_node(*node_, cfg, error)) << error;
  PoseProbe probe;
  const DeviceId estimate = node_->find_device(wire::Address(0, uint16_t(wire::Interface::Position2d), 5));
  ASSERT_NE(estimate, kNoDevice);
  node_->subscribe(estimate, &probe);

  sim_->command(0, {0.6, 0, 0.4});
  for (int cycle = 0; cycle < 2000; ++cycle) {
    sim_->step();
    server_->publish();  // odometry every cycle, detections every 4th
    node_->poll(0);
  }
  ASSERT_GT(probe.samples, 50u);
  const RobotInfo truth = sim_->robot(0);
  EXPECT_LT(std::hypot(probe.x - truth.pose.x, probe.y - truth.pose.y), 0.25)
      << "estimate " << probe.x << ", " << probe.y << " truth " << truth.pose.x << ", " << truth.pose.y;
  EXPECT_LT(std::abs(std::remainder(probe.a - truth.pose.a, 2 * M_PI)), 0.1);
}

TEST_F(MclDriver, RefusesLandmarksWithoutATableAndABadTable) {
  LoadedConfig cfg;
  std::string error;
  ASSERT_TRUE(load(mcl_config("", R"("position2d:0", "fiducial:0")"), cfg, error)) << error;
  EXPECT_FALSE(build_node(*node_, cfg, error));
  EXPECT_NE(error.find("landmark_table names no table"), std::string::npos) << error;

  std::ofstream(kDir + kTag + ".bad") << "troupe-landmarks 2\ngrid 0 0 1 2 2 1\nlandmarks 1 goal:0\n1 2\n";
  ASSERT_TRUE(load(mcl_config(kDir + kTag + ".bad", R"("position2d:0", "fiducial:0")"), cfg, error));
  Node other{Node::Options{}};
  sim::SimControl control;
  ASSERT_TRUE(other.add_driver(std::make_unique<RobocupServer>(*sim_, control), DriverSetup{}, error))
      << error;
  EXPECT_FALSE(build_node(other, cfg, error));
  EXPECT_NE(error.find(kTag + ".bad:4: ends after 1 of 4 pose lines"), std::string::npos) << error;
}

}  // namespace
}  // namespace troupe::robocup::test
