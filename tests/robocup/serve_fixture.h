// A RoboCup world served on a real TCP port from its own thread (paused:
// tests step it through simulation:0), for tests of the wire side.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <thread>

#include "host-sim/robocup/serve/serve_loop.h"
#include "tests/robocup/sim_fixture.h"
#include "wire/client/proxies.h"

namespace troupe::robocup::test {

/// A noise-free striker (yellow, at the centre spot facing +x) with
/// odometry, omni-vision, a front camera and a raw laser; a blue robot
/// without a player near its own goal; the ball 1 m ahead of the striker.
inline std::string served_world() {
  return R"(
interval_sim 10
seed 3
robocup_field ( length 9 width 5 )
ball ( radius 0.11 mass 0.43 deceleration 0.4 pose [1 0 0 0] )
referee ( goal_pause 1 duration 0 )
)" + robot("striker", "yellow", 0, 0, 0, pioneer_block(R"(
  motion_plugin ( plugin "diff_drive" max_speed 2 max_turn 6 accel 2.5 turn_accel 15 )
  sensor_plugin ( plugin "odometry" )
  sensor_plugin ( plugin "omnivision" name "omni" range 6 z 0.7 )
  sensor_plugin ( plugin "camera" name "front" x 0.2 fov 1.0 range 6 z 0.5 )
  sensor_plugin ( plugin "laser" name "laser" mode "raw" beams 181 range 8 z 0.3 )
)")) + robot("keeper", "blue", -4, 0, 0, pioneer_block("  motion_plugin ( plugin \"diff_drive\" )\n"));
}

class ServedWorld : public ::testing::Test {
 protected:
  void SetUp() override { serve(served_world()); }
  void TearDown() override {
    if (loop_) loop_->request_stop();
    if (thread_.joinable()) thread_.join();
  }
  void serve(const std::string& world) {
    std::string error;
    sim_ = make_sim(world, error);
    ASSERT_TRUE(sim_) << error;
    ASSERT_TRUE(sim_->problems().empty()) << sim_->problems().front();
    loop_ = std::make_unique<ServeLoop>(*sim_);
    ServeOptions o;
    o.port = 0;
    o.paused = true;
    ASSERT_TRUE(loop_->start(o, error)) << error;
    thread_ = std::thread([this] { loop_->run(); });
  }
  uint16_t port() const { return loop_->port(); }

  // The simulation belongs to the serving thread once it runs: tests only
  // reach it over the wire.
  std::unique_ptr<Simulation> sim_;
  std::unique_ptr<ServeLoop> loop_;
  std::thread thread_;
};

}  // namespace troupe::robocup::test
