// Bad node configs for odrive_can are refused at setup with a message that
// names the problem, and nothing is left half-configured.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include "tests/odrive/odrive_rig.h"

namespace troupe::testing {
namespace {

// Builds a node whose only driver is odrive_can with `options` (JSON members)
// providing `provides`; returns the error ("" when it was accepted).
std::string setup_error(const std::string& options, const std::string& provides = R"("position2d:0")") {
  int pair[2];
  EXPECT_EQ(socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, pair), 0);
  std::string opts =
      options.find("descriptor") != std::string::npos || options.find("can_interface") != std::string::npos
          ? options
          : "\"descriptor\": " + std::to_string(pair[0]) + (options.empty() ? "" : ", " + options);
  std::string json = R"({ "drivers": [ { "driver_type": "odrive_can", "driver": { )" + opts +
                     R"( }, "provides": [ )" + provides + " ] } ] }";
  std::string error;
  {
    Node node(Node::Options{});
    std::vector<uint8_t> bytes;
    build_node_from_json(node, json, bytes, error);
  }
  close(pair[0]);
  close(pair[1]);
  return error;
}

TEST(OdriveOptions, AcceptsAGoodConfig) {
  EXPECT_EQ(setup_error(R"("invert_right": true)"), "");
}

TEST(OdriveOptions, RefusesBadValuesByName) {
  EXPECT_NE(setup_error(R"("left_node_id": 3, "right_node_id": 3)").find("both 3"), std::string::npos);
  EXPECT_NE(setup_error(R"("right_node_id": 64)").find("0..63"), std::string::npos);
  EXPECT_NE(setup_error(R"("wheel_radius": 0)").find("wheel_radius"), std::string::npos);
  EXPECT_NE(setup_error(R"("track_width": -0.3)").find("track_width"), std::string::npos);
  EXPECT_NE(setup_error(R"("rate_hz": 0)").find("rate_hz"), std::string::npos);
  EXPECT_NE(setup_error(R"("heartbeat_timeout_ms": 0)").find("heartbeat_timeout_ms"), std::string::npos);
  EXPECT_NE(setup_error(R"("max_wheel_turns_s": 0)").find("max_wheel_turns_s"), std::string::npos);
}

TEST(OdriveOptions, UnknownKeysAreNamed) {
  std::string e = setup_error(R"("wheel_radus": 0.1)");
  EXPECT_NE(e.find("wheel_radus"), std::string::npos) << e;
  EXPECT_NE(e.find("rig.json"), std::string::npos) << e;  // the file
}

TEST(OdriveOptions, RefusesWrongDevices) {
  EXPECT_NE(setup_error("", R"("ranger:0")").find("odrive_can provides"), std::string::npos);
  EXPECT_NE(setup_error("", R"("power:0")").find("must provide a position2d"), std::string::npos);
  EXPECT_NE(setup_error("", R"("position2d:0", "power:0", "power:1")").find("at most one power"),
            std::string::npos);
}

TEST(OdriveOptions, ReportsABusThatCannotBeOpened) {
  std::string closed = setup_error(R"("descriptor": 1000)");
  EXPECT_NE(closed.find("descriptor 1000"), std::string::npos) << closed;
  // On a kernel without CAN this says so; with CAN, that nope0 does not exist.
  std::string missing = setup_error(R"("can_interface": "nope0")");
  EXPECT_TRUE(missing.find("nope0") != std::string::npos ||
              missing.find("no CAN support") != std::string::npos)
      << missing;
  std::string long_name = setup_error(R"("can_interface": "a-very-long-interface-name")");
  EXPECT_NE(long_name.find("1 to 15 characters"), std::string::npos) << long_name;
}

}  // namespace
}  // namespace troupe::testing
