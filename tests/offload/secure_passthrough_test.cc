// The passthrough driver's link as a secure session: a secure "robot"
// troupe-node (its config names its key and the desktop's), a "desktop"
// troupe-node whose passthrough names its identity and the robot's key
// (files relative to the desktop config's folder), and a client on the
// desktop. The desktop's mirror carries data and commands; with a node key
// that is not the robot's, nothing gets through and the link says why.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <functional>
#include <string>

#include "tests/support/secure_node.h"
#include "wire/client/proxies.h"

namespace troupe::testing {
namespace {

using client::Client;
using client::Position2dProxy;

const std::string kNode = std::string(TROUPE_BINARY_DIR) + "/bin/troupe-node";
constexpr double kDeadlineS = 30;  // bounds a failing test only

bool spin_until(Client& c, const std::function<bool()>& done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(kDeadlineS);
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    c.spin_once(20);
  }
  return true;
}

class SecurePassthrough : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    ASSERT_TRUE(robot_.make_keys({"desktop"}, error)) << error;
    ASSERT_TRUE(robot_.start(R"([{ "key": "desktop.pub" }])",
                             R"([ { "driver_type": "kinematic", "driver": { "max_speed": 1.0, "rate_hz": 20 },
                                    "provides": ["position2d:0"] } ])",
                             error))
        << error;
  }
  void TearDown() override {
    if (desktop_.running()) desktop_.stop();
    if (HasFailure())
      std::fprintf(stderr, "---- desktop\n%s---- robot\n%s", desktop_.err().c_str(),
                   robot_.node().err().c_str());
  }
  // The desktop's config beside the keys, naming them by relative paths (the
  // node runs from another folder), with `driver_extra` in passthrough's options.
  std::string desktop_config(const std::string& driver_extra) {
    const std::string path = robot_.path("desktop.json");
    std::ofstream(path) << R"({ "name": "desktop", "listen": "127.0.0.1", "port": )" << desktop_port_
                        << R"(, "drivers": [ { "driver_type": "passthrough",
      "driver": { "host": "127.0.0.1", "port": )"
                        << robot_.port() << R"(, "remote": ["position2d:0"], "backoff_min": 0.05,
                  "backoff_max": 0.5)"
                        << driver_extra << R"( }, "provides": ["position2d:3", "opaque:0"] } ] })";
    return path;
  }
  void start_desktop(const std::string& driver_extra) {
    std::string error;
    ASSERT_TRUE(desktop_.start({kNode, desktop_config(driver_extra)}, robot_.dir(), "desktop", error))
        << error;
    ASSERT_TRUE(wait_for_listener(desktop_port_, kDeadlineS)) << desktop_.err();
  }
  // Connects `c` and follows the passthrough's status device into status_.
  void watch_status(Client& c) {
    ASSERT_TRUE(c.connect(5000)) << c.error();
    c.add_data_handler([this](const wire::Message& m) {
      const wire::OpaqueBytes* o = m.body_as_OpaqueBytes();
      if (o != nullptr && o->bytes() != nullptr) status_.assign(o->bytes()->begin(), o->bytes()->end());
    });
    ASSERT_TRUE(c.open(wire::Address{0, uint16_t(wire::Interface::Opaque), 0})) << c.error();
  }

  SecureNodeProcess robot_;
  ChildProcess desktop_;
  uint16_t desktop_port_ = free_port();
  std::string status_;
};

TEST_F(SecurePassthrough, MirrorsASecureRobotsDeviceWithDataAndCommands) {
  start_desktop(R"(, "identity": "desktop", "node_key": "node.pub")");
  EXPECT_TRUE(desktop_.wait_for("through a secure session", true, 10'000)) << desktop_.err();
  Client c("127.0.0.1", desktop_port_);
  watch_status(c);
  ASSERT_TRUE(spin_until(c, [&] { return status_.find("\"state\":\"connected\"") != std::string::npos; }))
      << status_;
  Position2dProxy pos(c, 3);
  ASSERT_TRUE(pos.is_open()) << c.error();
  ASSERT_TRUE(spin_until(c, [&] { return pos.samples() >= 3; })) << "no data through the secure link";
  // A command goes the other way, sealed too: the robot moves.
  ASSERT_TRUE(pos.set_velocity(0.5f, 0, 0));
  ASSERT_TRUE(spin_until(c, [&] { return pos.x() > 0.2f; })) << "x stayed at " << pos.x();
  ASSERT_TRUE(pos.set_velocity(0, 0, 0));
  EXPECT_TRUE(robot_.node().wait_for("secure session with key ", true, 10'000)) << robot_.node().err();
}

TEST_F(SecurePassthrough, TheRobotsKeyAsHexDigitsWorksAsItsFile) {
  start_desktop(R"(, "identity": "desktop", "node_key": ")" + robot_.node_key_hex() + "\"");
  Client c("127.0.0.1", desktop_port_);
  ASSERT_TRUE(c.connect(5000)) << c.error();
  Position2dProxy pos(c, 3);
  ASSERT_TRUE(spin_until(c, [&] { return pos.samples() >= 3; })) << "no data through the secure link";
}

TEST_F(SecurePassthrough, AWrongNodeKeyIsRefusedAndTheLinkSaysWhy) {
  // The robot's key is node.pub; desktop.pub is another node's.
  start_desktop(R"(, "identity": "desktop", "node_key": "desktop.pub")");
  Client c("127.0.0.1", desktop_port_);
  watch_status(c);
  ASSERT_TRUE(spin_until(c, [&] {
    return status_.find(
               "during the secure handshake: it does not accept our key, does not hold the key we know "
               "for it") != std::string::npos;
  })) << status_;
  EXPECT_NE(status_.find("\"state\":\"reconnecting\""), std::string::npos) << status_;
  EXPECT_TRUE(desktop_.wait_for("during the secure handshake", true, 10'000)) << desktop_.err();
  EXPECT_TRUE(robot_.node().wait_for("does not hold this node's public key", true, 10'000))
      << robot_.node().err();
  Position2dProxy pos(c, 3);
  c.spin_for(300);
  EXPECT_EQ(pos.samples(), 0u) << "nothing of the robot may come through a refused link";
}

TEST_F(SecurePassthrough, AMissingIdentityFileStopsTheDesktopNamingIt) {
  const std::string config = desktop_config(R"(, "identity": "nobody", "node_key": "node.pub")");
  ProgramResult r = run_to_end({kNode, config}, 30'000);
  EXPECT_EQ(r.status, 78);
  EXPECT_NE(r.err.find(robot_.path("nobody")), std::string::npos) << r.err;
}

TEST_F(SecurePassthrough, ANodeKeyWithoutAnIdentityStopsTheDesktop) {
  const std::string config = desktop_config(R"(, "node_key": "node.pub")");
  ProgramResult r = run_to_end({kNode, config}, 30'000);
  EXPECT_EQ(r.status, 78);
  EXPECT_NE(r.err.find("node_key without identity"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace troupe::testing
