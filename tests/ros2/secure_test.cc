// troupe-ros2 to a secure troupe-node (a real process, keys from `troupe
// keygen`): it reads the node's devices through a secure session and hands
// its passthrough the same keys (--print-config shows them: an absolute
// identity and the node's key in hex); a wrong node key is refused, saying
// why. No DDS runs: --print-config stops before the bridge starts.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/secure_node.h"

namespace troupe::testing {
namespace {

const std::string kRos2 = std::string(TROUPE_BINARY_DIR) + "/bin/troupe-ros2";
constexpr int kRunMs = 30'000;  // bounds a failing run only

class SecureRos2 : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    ASSERT_TRUE(robot_.make_keys({"laptop"}, error)) << error;
    ASSERT_TRUE(robot_.start(R"([{ "key": "laptop.pub" }])",
                             R"([ { "driver_type": "kinematic", "provides": ["position2d:0"] } ])", error))
        << error;
  }
  ProgramResult print_config(const std::string& node_key) {
    std::vector<std::string> args = {kRos2, robot_.host(), "--print-config"};
    for (const std::string& a : secure_args(robot_, "laptop", node_key)) args.push_back(a);
    return run_to_end(args, kRunMs);
  }
  SecureNodeProcess robot_;
};

TEST_F(SecureRos2, ReadsASecureNodesDevicesAndGivesItsPassthroughTheKeys) {
  ProgramResult r = print_config("node.pub");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\"remote\": [\"0/position2d:0\"]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"identity\": \"" + robot_.path("laptop") + "\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"node_key\": \"" + robot_.node_key_hex() + "\""), std::string::npos) << r.out;
  EXPECT_TRUE(robot_.node().wait_for("secure session with key ", true, 10'000)) << robot_.node().err();
}

TEST_F(SecureRos2, AWrongNodeKeyIsRefusedSayingWhy) {
  ProgramResult r = print_config("laptop.pub");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.out, "");
  EXPECT_NE(
      r.err.find("during the secure handshake: it does not accept our key, does not hold the key we know "
                 "for it"),
      std::string::npos)
      << r.err;
  EXPECT_TRUE(robot_.node().wait_for("does not hold this node's public key", true, 10'000))
      << robot_.node().err();
}

}  // namespace
}  // namespace troupe::testing
