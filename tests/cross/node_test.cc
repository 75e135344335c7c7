// troupe-node cross-built for armhf, arm64 and big-endian powerpc, run under
// qemu-user, served to a client on the x86 host over loopback TCP.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/cross/qemu_node.h"
#include "tests/cross/test_client.h"

namespace troupe::cross {
namespace {

const wire::Address kBase(0, uint16_t(wire::Interface::Position2d), 0);

// A started node of a cross build with its board's first config.
struct Started {
  CrossBuild build;
  QemuNode node;
  std::string skip;
};

void start_node(const std::string& name, const std::string& config, Started& s) {
  if (!load_cross_build(name, s.build, s.skip)) return;
  std::string error;
  ASSERT_TRUE(s.node.start(s.build, s.build.node, s.build.path("configs/" + config), error)) << error;
}

TEST(CrossNode, ArmhfCoreServesAnEmptyDeviceList) {
  Started s;
  start_node("core-armhf", "core.bin", s);
  if (!s.skip.empty()) {
    GTEST_SKIP() << s.skip;
  }
  TestClient client;
  std::string error;
  ASSERT_TRUE(client.connect(s.node.port(), error)) << error;
  EXPECT_EQ(client.node_name(), "core");
  std::vector<wire::Address> devices;
  std::vector<std::string> drivers;
  ASSERT_TRUE(client.list_devices(devices, drivers)) << client.error();
  EXPECT_TRUE(devices.empty());
  // A device it does not have is refused by name, and the session goes on.
  ASSERT_FALSE(client.open(kBase));
  EXPECT_NE(client.error().find("no such device position2d:0"), std::string::npos) << client.error();
  ASSERT_TRUE(client.list_devices(devices, drivers)) << client.error();
  EXPECT_EQ(s.node.stop(), 0) << s.node.log();
  EXPECT_NE(s.node.log().find("stopped"), std::string::npos) << s.node.log();
}

TEST(CrossNode, Arm64DiffbotAnswersTimeSync) {
  Started s;
  start_node("diffbot-can-arm64", "diffbot-can.bin", s);
  if (!s.skip.empty()) {
    GTEST_SKIP() << s.skip;
  }
  TestClient client;
  std::string error;
  ASSERT_TRUE(client.connect(s.node.port(), error)) << error;
  EXPECT_EQ(client.node_name(), "diffbot-can");
  uint32_t seq = client.next_seq();
  auto& b = client.writer().start();
  const uint64_t sent_us = 0x0102030405060708ull;
  auto body = wire::CreateTimeSync(b, sent_us, 0, 0);
  ASSERT_TRUE(client.send(wire::make_header({}, wire::Kind::TimeSync, 0, seq, 0), wire::Body::TimeSync,
                          body.Union()));
  const wire::Message* reply = client.reply(wire::Kind::TimeSync, seq);
  ASSERT_NE(reply, nullptr) << client.error();
  const wire::TimeSync* sync = reply->body_as_TimeSync();
  ASSERT_NE(sync, nullptr);
  EXPECT_EQ(sync->client_send_us(), sent_us);
  EXPECT_GT(sync->node_recv_us(), 0u);
  EXPECT_GE(sync->node_send_us(), sync->node_recv_us());
  EXPECT_EQ(s.node.stop(), 0) << s.node.log();
}

// The kinematic board (ppc-node) on a big-endian and a little-endian target.
class KinematicNode : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    start_node(GetParam(), "ppc-node.bin", s_);
    if (!s_.skip.empty()) {
      GTEST_SKIP() << s_.skip;
    }
    std::string error;
    ASSERT_TRUE(client_.connect(s_.node.port(), error)) << error;
  }
  void TearDown() override {
    if (s_.node.running()) {
      EXPECT_EQ(s_.node.stop(), 0) << s_.node.log();
    }
  }

  // Reads position2d data until `done` holds for a sample; nullptr when the
  // stream ends first (the bound is against hangs only).
  const wire::Position2dState* wait_for_state(bool (*done)(const wire::Position2dState&)) {
    for (int i = 0; i < 400; ++i) {  // 20 s of samples at 20 Hz
      const wire::Message* msg = client_.data(kBase);
      if (msg == nullptr) return nullptr;
      const wire::Position2dState* state = msg->body_as_Position2dState();
      if (state && state->pose() && state->vel() && done(*state)) return state;
    }
    return nullptr;
  }

  Started s_;
  TestClient client_;
};

TEST_P(KinematicNode, ListsItsPosition2dDevice) {
  std::vector<wire::Address> devices;
  std::vector<std::string> drivers;
  ASSERT_TRUE(client_.list_devices(devices, drivers)) << client_.error();
  ASSERT_EQ(devices.size(), 1u);
  EXPECT_TRUE(devices[0] == kBase);
  EXPECT_EQ(drivers[0], "kinematic");
  EXPECT_EQ(client_.node_name(), "ppc-node");
}

TEST_P(KinematicNode, StreamsPosition2dAndFollowsVelocityCommands) {
  ASSERT_TRUE(client_.open(kBase)) << client_.error();
  // Data streams in with rising sequence numbers, the base at rest.
  uint32_t last_seq = 0;
  for (int i = 0; i < 5; ++i) {
    const wire::Message* msg = client_.data(kBase);
    ASSERT_NE(msg, nullptr) << client_.error();
    ASSERT_NE(msg->body_as_Position2dState(), nullptr);
    EXPECT_GT(msg->header()->seq(), last_seq);
    last_seq = msg->header()->seq();
    EXPECT_EQ(msg->body_as_Position2dState()->pose()->x(), 0.0f);
  }
  // Drive forward at 0.3 m/s while turning at 0.5 rad/s: the base reaches
  // the commanded velocities (within its acceleration limits) and moves.
  ASSERT_TRUE(client_.send_vel(kBase, 0.3f, 0.5f));
  const wire::Position2dState* moving = wait_for_state([](const wire::Position2dState& st) {
    return std::fabs(st.vel()->x() - 0.3f) < 1e-4f && std::fabs(st.vel()->a() - 0.5f) < 1e-4f;
  });
  ASSERT_NE(moving, nullptr) << client_.error();
  const wire::Position2dState* moved = wait_for_state(
      [](const wire::Position2dState& st) { return st.pose()->x() > 0.05f && st.pose()->a() > 0.05f; });
  ASSERT_NE(moved, nullptr) << client_.error();
  EXPECT_GT(moved->pose()->y(), 0.0f) << "turning left while driving forward moves +y";
  // A newer command replaces the older one: stop.
  ASSERT_TRUE(client_.send_vel(kBase, 0.0f, 0.0f));
  const wire::Position2dState* stopped = wait_for_state(
      [](const wire::Position2dState& st) { return st.vel()->x() == 0.0f && st.vel()->a() == 0.0f; });
  ASSERT_NE(stopped, nullptr) << client_.error();
}

TEST_P(KinematicNode, AnswersRequests) {
  // Geometry: the kinematic driver's default footprint, 0.5 m x 0.4 m.
  uint32_t seq = client_.next_seq();
  client_.writer().start();
  ASSERT_TRUE(client_.send(
      wire::make_header(kBase, wire::Kind::Request, uint8_t(wire::Position2dReqSub::Geometry), seq, 0)));
  const wire::Message* ack = client_.reply(wire::Kind::Ack, seq);
  ASSERT_NE(ack, nullptr) << client_.error();
  const wire::Position2dGeometry* geometry = ack->body_as_Position2dGeometry();
  ASSERT_TRUE(geometry && geometry->size());
  EXPECT_FLOAT_EQ(geometry->size()->x(), 0.5f);
  EXPECT_FLOAT_EQ(geometry->size()->y(), 0.4f);

  // Set odometry, then read it back from the data.
  seq = client_.next_seq();
  auto& b = client_.writer().start();
  wire::Pose2d pose(-1.25f, 2.5f, 0.75f);
  auto body = wire::CreatePosition2dSetOdom(b, &pose);
  ASSERT_TRUE(client_.send(
      wire::make_header(kBase, wire::Kind::Request, uint8_t(wire::Position2dReqSub::SetOdometry), seq, 0),
      wire::Body::Position2dSetOdom, body.Union()));
  ASSERT_NE(client_.reply(wire::Kind::Ack, seq), nullptr) << client_.error();
  ASSERT_TRUE(client_.open(kBase)) << client_.error();
  // The first sample pushed on open may predate the request.
  const wire::Position2dState* state =
      wait_for_state([](const wire::Position2dState& st) { return st.pose()->x() == -1.25f; });
  ASSERT_NE(state, nullptr) << client_.error();
  EXPECT_FLOAT_EQ(state->pose()->y(), 2.5f);
  EXPECT_FLOAT_EQ(state->pose()->a(), 0.75f);

  // An unsupported request subtype gets a Nack, not silence.
  seq = client_.next_seq();
  client_.writer().start();
  ASSERT_TRUE(client_.send(wire::make_header(kBase, wire::Kind::Request, 99, seq, 0)));
  const wire::Message* nack = client_.reply(wire::Kind::Nack, seq);
  ASSERT_NE(nack, nullptr) << client_.error();
  ASSERT_NE(nack->body_as_Error(), nullptr);
  EXPECT_EQ(nack->body_as_Error()->code(), wire::ErrorCode::Unsupported);
}

TEST_P(KinematicNode, RefusesABadFrameAndServesTheOtherClients) {
  ASSERT_TRUE(client_.open(kBase)) << client_.error();
  TestClient bad;
  std::string error;
  ASSERT_TRUE(bad.connect(s_.node.port(), error)) << error;
  // A well-framed buffer whose root offset points far outside it.
  const uint8_t garbage[] = {12, 0, 0, 0, 0xF0, 0xFF, 0xFF, 0x7F, 1, 2, 3, 4, 5, 6, 7, 8};
  ASSERT_TRUE(bad.send_raw(garbage));
  const wire::Message* reply = bad.next();
  ASSERT_NE(reply, nullptr) << bad.error();
  EXPECT_EQ(reply->header()->kind(), wire::Kind::Error);
  ASSERT_NE(reply->body_as_Error(), nullptr);
  EXPECT_EQ(reply->body_as_Error()->code(), wire::ErrorCode::VerifyFailed);
  EXPECT_EQ(bad.next(), nullptr);
  EXPECT_TRUE(bad.closed()) << "the node closes a connection after its Error";
  // The first client still gets data and may still command.
  ASSERT_NE(client_.data(kBase), nullptr) << client_.error();
  ASSERT_TRUE(client_.send_vel(kBase, 0.1f, 0.0f));
  std::vector<wire::Address> devices;
  std::vector<std::string> drivers;
  EXPECT_TRUE(client_.list_devices(devices, drivers)) << client_.error();
  EXPECT_NE(s_.node.log().find("bad frame"), std::string::npos) << s_.node.log();
}

INSTANTIATE_TEST_SUITE_P(Targets, KinematicNode, ::testing::Values("ppc-node-powerpc", "ppc-node-armhf"),
                         [](const auto& param_info) {
                           std::string name = param_info.param;
                           return name.substr(name.rfind('-') + 1);
                         });

}  // namespace
}  // namespace troupe::cross
