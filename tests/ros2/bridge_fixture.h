// What the tests of the bridge between real programs share: a DDS domain
// of the test's own, troupe-sim and troupe-ros2 as child processes, a Troupe
// client to the simulator for ground truth, and ways to drive and wait.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "ros2_msgsPubSubTypes.h"
#include "tests/ros2/dds_env.h"
#include "tests/ros2/fastdds_peer.h"
#include "tests/support/child_process.h"
#include "wire/client/client.h"
#include "wire/client/proxies.h"

namespace troupe::testing::ros2 {

namespace fdds = eprosima::fastdds::dds;

using LaserScan = sensor_msgs::msg::dds_::LaserScan_;
using Odometry = nav_msgs::msg::dds_::Odometry_;
using Twist = geometry_msgs::msg::dds_::Twist_;
using TFMessage = tf2_msgs::msg::dds_::TFMessage_;
using Clock = rosgraph_msgs::msg::dds_::Clock_;
using OccupancyGrid = nav_msgs::msg::dds_::OccupancyGrid_;
using Range = sensor_msgs::msg::dds_::Range_;
using DiagnosticArray = diagnostic_msgs::msg::dds_::DiagnosticArray_;
using ParticipantEntitiesInfo = rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_;
using PoseWithCovarianceStamped = geometry_msgs::msg::dds_::PoseWithCovarianceStamped_;

inline const std::string kBin = std::string(TROUPE_BINARY_DIR) + "/bin";
inline const std::string kWorlds = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds";
constexpr PeerQos kSensorQos{false, false, 50};
constexpr PeerQos kReliable{true, false, 50};
constexpr PeerQos kLatched{true, true, 1};
// Bounds against hangs on a loaded machine, never measurements.
constexpr int kWaitMs = 20000;

inline uint64_t stamp_us(const builtin_interfaces::msg::dds_::Time_& t) {
  return uint64_t(t.sec()) * 1'000'000u + t.nanosec() / 1000u;
}

inline double yaw_of(const geometry_msgs::msg::dds_::Quaternion_& q) {
  return std::atan2(2 * (q.w() * q.z() + q.x() * q.y()), 1 - 2 * (q.y() * q.y() + q.z() * q.z()));
}

inline Twist twist(double vx, double va) {
  Twist t;
  t.linear().x(vx);
  t.angular().z(va);
  return t;
}

class BridgeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_GT(domain_.id(), 0) << "no free DDS domain";
    dir_ = make_temp_dir("troupe-ros2-test");
    ASSERT_FALSE(dir_.empty());
    // The bridge (a child process) reads its DDS configuration from here.
    setenv("CYCLONEDDS_URI", cyclone_loopback_config().c_str(), 1);
  }
  void TearDown() override {
    bridge_.stop();
    sim_.stop();
    if (HasFailure()) {
      std::fprintf(stderr, "---- troupe-sim\n%s---- troupe-ros2\n%s", sim_.out().c_str(),
                   bridge_.out().c_str());
    }
    remove_tree(dir_);
  }

  void start_sim(const std::string& world, std::vector<std::string> extra = {}) {
    if (sim_port_ == 0) sim_port_ = free_port();
    std::vector<std::string> argv = {kBin + "/troupe-sim", kWorlds + "/" + world, "--port",
                                     std::to_string(sim_port_), "--no-view"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    std::string error;
    ASSERT_TRUE(sim_.start_logged(argv, dir_ + "/sim.log", error)) << error;
    ASSERT_TRUE(wait_for_listener(sim_port_, 20)) << "troupe-sim did not listen";
  }
  void start_bridge(std::vector<std::string> extra = {}) {
    std::vector<std::string> argv = {kBin + "/troupe-ros2", "localhost:" + std::to_string(sim_port_),
                                     "--domain", std::to_string(domain_.id())};
    argv.insert(argv.end(), extra.begin(), extra.end());
    std::string error;
    ASSERT_TRUE(bridge_.start_logged(argv, dir_ + "/bridge.log", error)) << error;
    ASSERT_TRUE(bridge_.wait_for("ros2 ready", true, kWaitMs)) << "troupe-ros2 did not start";
  }
  // A Troupe client straight to the simulator: ground truth and the devices'
  // own samples.
  troupe::client::Client& sim_client() {
    if (!client_) {
      client_ = std::make_unique<troupe::client::Client>("127.0.0.1", sim_port_);
      EXPECT_TRUE(client_->connect(5000)) << client_->error();
      simulation_ = std::make_unique<troupe::client::SimulationProxy>(*client_);
    }
    return *client_;
  }
  troupe::client::Pose2 ground_truth(const std::string& robot = "r0") {
    sim_client();
    troupe::client::Pose2 p;
    EXPECT_TRUE(simulation_->get_pose(robot, p)) << client_->error();
    return p;
  }
  // Publishes `t` every 100 ms until `done` holds (at most kWaitMs).
  template <class Done>
  bool drive_until(fdds::DataWriter* w, Twist t, Done done) {
    for (int waited = 0; waited < kWaitMs; waited += 100) {
      w->write(&t);
      sim_client().spin_for(100);
      if (done()) return true;
    }
    return false;
  }
  // The ground truth no longer changes (the base stopped).
  bool stopped(const std::string& robot = "r0") {
    troupe::client::Pose2 a = ground_truth(robot);
    for (int waited = 0; waited < kWaitMs; waited += 500) {
      sim_client().spin_for(500);
      const troupe::client::Pose2 b = ground_truth(robot);
      if (std::hypot(b.x - a.x, b.y - a.y) < 1e-4 && std::fabs(b.a - a.a) < 1e-4) return true;
      a = b;
    }
    return false;
  }
  // Waits until `writer` sees a subscriber (the bridge's reader).
  static bool wait_matched(fdds::DataWriter* w) {
    for (int waited = 0; waited < kWaitMs; waited += 50) {
      if (matched(w) > 0) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
  }

  DdsDomain domain_;
  std::string dir_;
  uint16_t sim_port_ = 0;
  ChildProcess sim_, bridge_;
  std::unique_ptr<troupe::client::Client> client_;
  std::unique_ptr<troupe::client::SimulationProxy> simulation_;
};

}  // namespace troupe::testing::ros2
