// `troupe record` against a secure troupe-node: it records a device through
// a secure session (--identity, --node-key), `troupe play` serves the log
// again and a client sees exactly the recorded samples; with a node key
// that is not the node's, nothing is recorded and the user is told why.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "tests/record/process.h"
#include "tests/support/secure_node.h"
#include "wire/client/client.h"
#include "wire/record/log_file.h"

namespace troupe::testing {
namespace {

// A sample as its sender stamped it: the device and the time, us.
struct Stamp {
  uint64_t key = 0;  // wire::address_key
  uint64_t time_us = 0;
  bool operator==(const Stamp&) const = default;
};

Stamp stamp_of(const wire::Message& msg) {
  return {wire::address_key(msg.header()->addr()), wire::time_us(*msg.header())};
}

class SecureRecord : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    ASSERT_TRUE(robot_.make_keys({"laptop", "stranger"}, error)) << error;
    ASSERT_TRUE(robot_.start(R"([{ "key": "laptop.pub" }])", kKinematicBase, error)) << error;
  }
  // `troupe record` of the robot's position2d:0 into `log`, as `identity`
  // holding `node_key`.
  Outcome record(const std::string& log, const std::string& identity, const std::string& node_key) {
    std::vector<std::string> args = {bin("bin/troupe"), "record", robot_.host(), "position2d:0", "-o", log,
                                     "--count",         "5"};
    for (const std::string& a : secure_args(robot_, identity, node_key)) args.push_back(a);
    return run_program(args);
  }

  SecureNodeProcess robot_;
};

TEST_F(SecureRecord, RecordsADeviceOfASecureNodeAndTheLogPlaysBack) {
  const std::string log = robot_.path("run.trl");
  Outcome rec = record(log, "laptop", "node.pub");
  ASSERT_EQ(rec.rc, 0) << rec.err;
  EXPECT_TRUE(robot_.node().wait_for("secure session with key ", true, 10'000)) << robot_.node().err();

  std::vector<Stamp> recorded;
  record::LogReader reader;
  std::string error;
  ASSERT_TRUE(reader.open(log, error)) << error;
  for (record::LogRecord r; reader.next(r);) {
    if (r.message->header()->kind() == wire::Kind::Data) recorded.push_back(stamp_of(*r.message));
  }
  ASSERT_EQ(recorded.size(), 5u) << reader.problem();

  // troupe play serves it (plain, on loopback); --wait holds it until the
  // client has opened the device, so every sample reaches it.
  const uint16_t port = free_port();
  Process player({bin("bin/troupe"), "play", log, "--port", std::to_string(port), "--wait"});
  ASSERT_TRUE(player.wait_listening(port)) << player.err();
  client::Client c("127.0.0.1", port);
  ASSERT_TRUE(c.connect()) << c.error();
  std::vector<Stamp> played;
  c.add_data_handler([&](const wire::Message& msg) { played.push_back(stamp_of(msg)); });
  wire::Address addr;
  ASSERT_TRUE(c.resolve("position2d:0", addr)) << c.error();
  ASSERT_TRUE(c.open(addr, wire::Access::Read)) << c.error();
  // Bounds a failing test only: the player exits when the log ends.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (player.running() && std::chrono::steady_clock::now() < deadline) c.spin_once(50);
  c.spin_for(100);
  EXPECT_EQ(player.wait(), 0) << player.err();
  EXPECT_EQ(played, recorded);
}

TEST_F(SecureRecord, AWrongNodeKeyIsRefusedAndNothingIsRecorded) {
  const std::string log = robot_.path("wrong.trl");
  Outcome rec = record(log, "laptop", "stranger.pub");
  EXPECT_EQ(rec.rc, 1);
  EXPECT_NE(rec.err.find("during the secure handshake"), std::string::npos) << rec.err;
  EXPECT_NE(rec.err.find("does not hold the key we know for it"), std::string::npos) << rec.err;
  EXPECT_TRUE(robot_.node().wait_for("does not hold this node's public key", true, 10'000))
      << robot_.node().err();
  record::LogReader reader;
  std::string error;
  EXPECT_FALSE(reader.open(log, error)) << "a refused session writes no log";
}

TEST_F(SecureRecord, ANodeKeyWithoutAnIdentityIsAMistakeSaidBeforeConnecting) {
  Outcome rec = run_program({bin("bin/troupe"), "record", robot_.host(), "position2d:0", "-o",
                             robot_.path("none.trl"), "--node-key", robot_.path("node.pub")});
  EXPECT_EQ(rec.rc, 1);
  EXPECT_NE(rec.err.find("a secure session needs --identity FILE (our secret key) with --node-key"),
            std::string::npos)
      << rec.err;
}

}  // namespace
}  // namespace troupe::testing
