// A node running the p2os driver against the Pioneer emulator on a pty,
// beside a kinematic driver, with a client on loopback TCP opening all of
// their devices. Everything steps in this thread (tests/device_harness).
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "host-sim/emulators/p2os/pioneer_emulator.h"
#include "tests/device_harness/device_harness.h"

namespace troupe::testing {

inline const wire::Address kBase(0, uint16_t(wire::Interface::Position2d), 0);
inline const wire::Address kSonar(0, uint16_t(wire::Interface::Ranger), 0);
inline const wire::Address kPower(0, uint16_t(wire::Interface::Power), 0);
inline const wire::Address kBumper(0, uint16_t(wire::Interface::Bumper), 0);
inline const wire::Address kOther(0, uint16_t(wire::Interface::Position2d), 1);  // the kinematic driver

// The rig without GoogleTest's fixture, so a test parameterised over the
// serial drivers can hold one (tests/serial_port/serial_driver_alloc_test).
struct P2osRig {
  /// The node's JSON config; `options` are extra p2os options ("k": v, ...).
  std::string config(const std::string& options) const {
    std::string driver = "\"port\": \"" + dir_.file("pioneer") + "\"";
    if (!options.empty()) driver += ", " + options;
    return R"({ "name": "p2os-test", "drivers": [
      { "driver_type": "p2os", "driver": { )" +
           driver + R"( },
        "provides": ["position2d:0", "ranger:0", "power:0", "bumper:0"] },
      { "driver_type": "kinematic", "driver": { "rate_hz": 20 }, "provides": ["position2d:1"] } ] })";
  }

  /// Starts the robot, then the node, then the client.
  void start(emulators::PioneerEmulator::Config robot_config = {}, const std::string& options = "",
             emulators::PioneerWorld* world = nullptr) {
    robot_ = std::make_unique<emulators::PioneerEmulator>(robot_config, world);
    std::string error;
    ASSERT_TRUE(robot_->open(dir_.file("pioneer"), error)) << error;
    loop_.add([this](uint64_t now) { robot_->step(now); });
    start_node(options);
  }

  void start_node(const std::string& options = "") {
    std::string error;
    ASSERT_TRUE(node_.start(config(options), error)) << error;
    ASSERT_TRUE(client_.connect(node_.port(), error)) << error;
    for (const wire::Address& a : {kBase, kSonar, kPower, kBumper, kOther}) client_.open(a);
    loop_.add(node_);
    loop_.add(client_);
  }

  /// The driver reports the base under control (data without a stall).
  bool connected() const {
    const wire::Position2dState* s = position_state(client_, kBase);
    return s != nullptr && !s->stall();
  }
  bool reports_stall() const {
    const wire::Position2dState* s = position_state(client_, kBase);
    return s != nullptr && s->stall();
  }
  void connect() {
    ASSERT_TRUE(loop_.run_until([&] { return connected(); }, 15)) << "the driver never connected";
  }

  /// The driver's odometric pose.
  wire::Pose2d pose() const {
    const wire::Position2dState* s = position_state(client_, kBase);
    return s && s->pose() ? *s->pose() : wire::Pose2d();
  }
  /// Waits until the robot has stopped and the driver's pose has caught up
  /// with the robot's within `tolerance_m`.
  bool settles_at_robot_pose(double tolerance_m) {
    return loop_.run_until(
        [&] {
          const emulators::PioneerPose& p = robot_->pose();
          return robot_->left_mps() == 0 && robot_->right_mps() == 0 &&
                 std::fabs(pose().x() - p.x) < tolerance_m && std::fabs(pose().y() - p.y) < tolerance_m;
        },
        10);
  }

  TempDir dir_;
  std::unique_ptr<emulators::PioneerEmulator> robot_;
  NodeUnderTest node_;
  WireClient client_;
  Loop loop_;
};

class P2osNode : public ::testing::Test, public P2osRig {};

}  // namespace troupe::testing
