// troupe-node cross-built for armhf, arm64 and big-endian powerpc, run under
// qemu-user, served over loopback TCP to the C++ client library on the x86
// host.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/cross/qemu_node.h"
#include "wire/client/proxies.h"

namespace troupe::cross {
namespace {

using client::Client;
using client::Position2dProxy;

const wire::Address kBase(0, uint16_t(wire::Interface::Position2d), 0);
// Bounds a wait for something the node must do (hangs, not speed).
constexpr int kWaitMs = 20000;

Client::Options no_reconnect() {
  Client::Options o;
  o.name = "cross-test";
  o.reconnect = false;
  return o;
}

// A node of a cross build started with one of its compiled configs; `skip`
// says why not when the build or qemu-user is missing.
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

// Spins the client until `done()` holds; false when it does not within
// kWaitMs.
template <typename Done>
bool spin_until(Client& c, Done done) {
  for (int waited = 0; waited < kWaitMs && !done(); waited += 10) c.spin_once(10);
  return done();
}

TEST(CrossNode, ArmhfCoreServesAnEmptyDeviceList) {
  Started s;
  start_node("core-armhf", "core.bin", s);
  if (!s.skip.empty()) {
    GTEST_SKIP() << s.skip;
  }
  Client c("127.0.0.1", s.node.port(), no_reconnect());
  ASSERT_TRUE(c.connect()) << c.error();
  EXPECT_EQ(c.node_name(), "core");
  std::vector<client::DeviceEntry> devices;
  ASSERT_TRUE(c.device_list(devices)) << c.error();
  EXPECT_TRUE(devices.empty());
  // A device it does not have is refused by name, and the session goes on.
  EXPECT_FALSE(c.open(kBase));
  EXPECT_NE(c.error().find("no such device position2d:0"), std::string::npos) << c.error();
  EXPECT_TRUE(c.sync()) << c.error();
  EXPECT_EQ(s.node.stop(), 0) << s.node.log();
  EXPECT_NE(s.node.log().find("stopped"), std::string::npos) << s.node.log();
}

// The diffbot-can board's real odrive_can driver, cross-built for arm64,
// drives ODrive axes emulated on the host: troupe-emulate-odrive runs the node
// (under qemu-user) with a socketpair for the CAN bus as descriptor 3. Only
// little-endian targets: a can_frame's id is in the byte order of the
// machine, which a real bus shares with its node but this socketpair does not.
TEST(CrossNode, Arm64DiffbotDrivesEmulatedOdriveAxes) {
  Started s;
  if (!load_cross_build("diffbot-can-arm64", s.build, s.skip)) {
    GTEST_SKIP() << s.skip;
  }
  QemuNode::Extras emulated;
  emulated.wrapper = {TROUPE_ODRIVE_EMU, "--status-ms", "0", "--"};
  std::string error;
  ASSERT_TRUE(
      s.node.start(s.build, s.build.node, s.build.path("configs/diffbot-can-emulated.bin"), error, emulated))
      << error;
  Client c("127.0.0.1", s.node.port(), no_reconnect());
  ASSERT_TRUE(c.connect()) << c.error();
  EXPECT_EQ(c.node_name(), "diffbot-can");
  ASSERT_TRUE(c.sync()) << c.error();  // TimeSync: 64-bit times both ways
  std::vector<client::DeviceEntry> devices;
  ASSERT_TRUE(c.device_list(devices)) << c.error();
  ASSERT_EQ(devices.size(), 2u);
  EXPECT_EQ(devices[0].text(), "position2d:0");
  EXPECT_EQ(devices[1].text(), "power:0");
  EXPECT_EQ(devices[0].driver, "odrive_can");

  Position2dProxy base(c);
  ASSERT_TRUE(base.is_open()) << c.error();
  ASSERT_TRUE(base.set_velocity(0.2f, 0.0f, 0.0f));
  // The axes ramp up; the driver's odometry comes from their encoders.
  EXPECT_TRUE(spin_until(c, [&] { return std::fabs(base.velocity().x - 0.2f) < 0.01f && base.x() > 0.02f; }))
      << "velocity " << base.velocity().x << " m/s, x " << base.x() << " m\n"
      << s.node.log();
  EXPECT_NEAR(base.velocity().a, 0.0f, 0.01f);
  EXPECT_EQ(s.node.stop(), 0) << s.node.log();
}

// Without a CAN bus (this machine's kernel has none) the node refuses to
// start, naming the driver instance, rather than serving half a robot.
TEST(CrossNode, Arm64DiffbotWithoutCanBusRefusesToStart) {
  Started s;
  if (!load_cross_build("diffbot-can-arm64", s.build, s.skip)) {
    GTEST_SKIP() << s.skip;
  }
  std::string error;
  EXPECT_FALSE(s.node.start(s.build, s.build.node, s.build.path("configs/diffbot-can.bin"), error));
  EXPECT_EQ(s.node.exited(), 1) << error;
  EXPECT_NE(error.find("drivers[0] (odrive_can)"), std::string::npos) << error;
  EXPECT_NE(error.find("not starting"), std::string::npos) << error;
}

// The kinematic board (ppc-node) on a big-endian and a little-endian target.
class KinematicNode : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    start_node(GetParam(), "ppc-node.bin", s_);
    if (!s_.skip.empty()) {
      GTEST_SKIP() << s_.skip;
    }
    client_ = std::make_unique<Client>("127.0.0.1", s_.node.port(), no_reconnect());
    ASSERT_TRUE(client_->connect()) << client_->error();
  }
  void TearDown() override {
    if (s_.node.running()) {
      EXPECT_EQ(s_.node.stop(), 0) << s_.node.log();
    }
  }

  Started s_;
  std::unique_ptr<Client> client_;
};

TEST_P(KinematicNode, ListsItsPosition2dDevice) {
  EXPECT_EQ(client_->node_name(), "ppc-node");
  std::vector<client::DeviceEntry> devices;
  ASSERT_TRUE(client_->device_list(devices)) << client_->error();
  ASSERT_EQ(devices.size(), 1u);
  EXPECT_EQ(devices[0].text(), "position2d:0");
  EXPECT_EQ(devices[0].driver, "kinematic");
}

TEST_P(KinematicNode, StreamsPosition2dAndFollowsVelocityCommands) {
  std::vector<uint32_t> seqs;
  client_->add_data_handler([&](const wire::Message& m) { seqs.push_back(m.header()->seq()); });
  Position2dProxy base(*client_);
  ASSERT_TRUE(base.is_open()) << client_->error();
  // Data streams in with rising sequence numbers, the base at rest.
  ASSERT_TRUE(spin_until(*client_, [&] { return seqs.size() >= 5; }));
  for (size_t i = 1; i < seqs.size(); ++i) EXPECT_GT(seqs[i], seqs[i - 1]);
  EXPECT_EQ(base.x(), 0.0f);
  EXPECT_EQ(base.velocity().x, 0.0f);

  // Forward at 0.3 m/s turning left at 0.5 rad/s: the base reaches the
  // commanded velocities (within its acceleration limits) and moves.
  ASSERT_TRUE(base.set_velocity(0.3f, 0.0f, 0.5f));
  EXPECT_TRUE(spin_until(*client_,
                         [&] {
                           return std::fabs(base.velocity().x - 0.3f) < 1e-4f &&
                                  std::fabs(base.velocity().a - 0.5f) < 1e-4f;
                         }))
      << "velocity " << base.velocity().x << " m/s, " << base.velocity().a << " rad/s";
  EXPECT_TRUE(spin_until(*client_, [&] { return base.x() > 0.05f && base.a() > 0.05f; }));
  EXPECT_GT(base.y(), 0.0f) << "turning left while driving forward moves +y";

  // A newer command replaces the older one: stop.
  ASSERT_TRUE(base.set_velocity(0.0f, 0.0f, 0.0f));
  EXPECT_TRUE(spin_until(*client_, [&] { return base.velocity().x == 0.0f && base.velocity().a == 0.0f; }));
}

TEST_P(KinematicNode, AnswersRequests) {
  Position2dProxy base(*client_);
  ASSERT_TRUE(base.is_open()) << client_->error();
  // Geometry: the kinematic driver's default footprint, 0.5 m x 0.4 m.
  wire::Vec3 size;
  wire::Pose3d offset;
  ASSERT_TRUE(base.geometry(size, offset)) << client_->error();
  EXPECT_FLOAT_EQ(size.x(), 0.5f);
  EXPECT_FLOAT_EQ(size.y(), 0.4f);

  // Set odometry, then read it back from the data.
  ASSERT_TRUE(base.set_odometry(-1.25f, 2.5f, 0.75f)) << client_->error();
  EXPECT_TRUE(spin_until(*client_, [&] { return base.x() == -1.25f; })) << base.x();
  EXPECT_FLOAT_EQ(base.y(), 2.5f);
  EXPECT_FLOAT_EQ(base.a(), 0.75f);

  // An unsupported request subtype gets a Nack, not silence.
  client::Reply reply = client_->request(kBase, 99);
  EXPECT_EQ(reply.status, client::Reply::Status::Nack);
  EXPECT_EQ(reply.code, wire::ErrorCode::Unsupported);
}

TEST_P(KinematicNode, RefusesABadFrameAndServesTheOtherClients) {
  Position2dProxy base(*client_);
  ASSERT_TRUE(base.is_open()) << client_->error();
  Client bad("127.0.0.1", s_.node.port(), no_reconnect());
  ASSERT_TRUE(bad.connect()) << bad.error();
  // A well-framed buffer whose root offset points far outside it.
  const uint8_t garbage[] = {12, 0, 0, 0, 0xF0, 0xFF, 0xFF, 0x7F, 1, 2, 3, 4, 5, 6, 7, 8};
  ASSERT_TRUE(bad.send_frame(garbage));
  EXPECT_TRUE(spin_until(bad, [&] { return !bad.connected(); }))
      << "the node keeps a client that sent garbage";
  EXPECT_NE(bad.error().find("node closed the connection: FlatBuffers verifier refused the buffer"),
            std::string::npos)
      << bad.error();
  // The first client still gets data and may still command.
  uint64_t samples = base.samples();
  EXPECT_TRUE(spin_until(*client_, [&] { return base.samples() > samples + 2; }));
  ASSERT_TRUE(base.set_velocity(0.1f, 0.0f, 0.0f));
  EXPECT_TRUE(spin_until(*client_, [&] { return base.velocity().x > 0.0f; }));
  EXPECT_TRUE(client_->connected());
  EXPECT_NE(s_.node.log().find("bad frame"), std::string::npos) << s_.node.log();
}

INSTANTIATE_TEST_SUITE_P(Targets, KinematicNode, ::testing::Values("ppc-node-powerpc", "ppc-node-armhf"),
                         [](const auto& param_info) {
                           std::string name = param_info.param;
                           return name.substr(name.rfind('-') + 1);
                         });

}  // namespace
}  // namespace troupe::cross
