// troupe-ros2 bridging a secure troupe-node (keys from `troupe keygen`) into
// another vendor's DDS: it opens its session with --identity and
// --node-key, the node's odometry reaches a Fast DDS subscriber and a
// Fast DDS cmd_vel drives the node's base. The node's own log shows the
// secure session; a plain client of the same node is refused, so the data
// can only have come through the session.
#include <string>
#include <vector>

#include "tests/ros2/bridge_fixture.h"
#include "tests/support/secure_node.h"

namespace {

using namespace troupe::testing;
using namespace troupe::testing::ros2;

class SecureBridgeTest : public BridgeTest {
 protected:
  void SetUp() override {
    BridgeTest::SetUp();
    ASSERT_FALSE(HasFatalFailure());
    std::string error;
    ASSERT_TRUE(robot_.make_keys({"laptop"}, error)) << error;
    ASSERT_TRUE(robot_.start(R"([{ "key": "laptop.pub" }])", kKinematicBase, error)) << error;
    std::vector<std::string> argv = {kBin + "/troupe-ros2", robot_.host(), "--domain",
                                     std::to_string(domain_.id())};
    for (const std::string& a : secure_args(robot_, "laptop", "node.pub")) argv.push_back(a);
    ASSERT_TRUE(bridge_.start_logged(argv, dir_ + "/bridge.log", error)) << error;
    ASSERT_TRUE(bridge_.wait_for("ros2 ready", true, kWaitMs))
        << "troupe-ros2 did not start: " << bridge_.out();
  }
  void TearDown() override {
    if (HasFailure()) std::fprintf(stderr, "---- troupe-node\n%s", robot_.node().err().c_str());
    BridgeTest::TearDown();
  }

  SecureNodeProcess robot_;
};

TEST_F(SecureBridgeTest, OdometryOfASecureNodeReachesDdsAndCmdVelDrivesIt) {
  EXPECT_TRUE(robot_.node().wait_for("secure session with key ", true, kWaitMs)) << robot_.node().err();
  ProgramResult plain = run_to_end({kBin + "/troupe", "ls", robot_.host()}, kWaitMs);
  EXPECT_NE(plain.status, 0) << "the node serves secure sessions only";

  FastDdsPeer peer(domain_.id());
  ASSERT_TRUE(peer.ok());
  fdds::DataReader* odoms =
      peer.reader("rt/odom", peer.register_type<nav_msgs::msg::dds_::Odometry_PubSubType>(), kReliable);
  fdds::DataWriter* cmd =
      peer.writer("rt/cmd_vel", peer.register_type<geometry_msgs::msg::dds_::Twist_PubSubType>(), kReliable);
  ASSERT_TRUE(odoms && cmd);

  // The base stands at its start: odometry at the origin.
  Odometry o;
  int standing = 0;
  for (int waited = 0; waited < kWaitMs && standing < 3; waited += 100) {
    if (!take(odoms, o, 100)) continue;
    EXPECT_EQ(o.header().frame_id(), "odom");  // robot 0 of a node: the root namespace
    EXPECT_EQ(o.pose().pose().position().x(), 0.0);
    standing++;
  }
  ASSERT_GE(standing, 3) << "no odometry of the secure node reached DDS";

  // Driven forward through the bridge's session, it leaves the origin.
  ASSERT_TRUE(wait_matched(cmd)) << "the bridge's cmd_vel reader was not matched";
  Twist forward = twist(0.3, 0);
  double x = 0;
  for (int waited = 0; waited < kWaitMs && x < 0.1; waited += 100) {
    cmd->write(&forward);
    if (take(odoms, o, 100)) x = o.pose().pose().position().x();
  }
  EXPECT_GE(x, 0.1) << "cmd_vel did not reach the secure node's base";
  Twist zero;
  cmd->write(&zero);
}

}  // namespace
