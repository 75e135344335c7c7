// Secure sessions on the boards: the secure troupe-node (BOARD_SECURE, Noise
// IK on the target's libsodium) cross-built for armhf, arm64 (static) and
// big-endian powerpc, run under qemu-user with a config that names its key
// and the one client it accepts; the x86 client library, holding that
// client's identity, completes the handshake and reads a device. A client
// whose key the node does not list is refused while the known one keeps
// being served.
#include <gtest/gtest.h>

#include <fstream>

#include "tests/cross/qemu_node.h"
#include "wire/client/proxies.h"
#include "wire/noise/client_keys.h"
#include "wire/noise/key_file.h"
#include "wire/noise/noise_transport.h"

namespace troupe::cross {
namespace {

using client::Client;
using client::Position2dProxy;

const std::string kHostBin = std::string(TROUPE_BINARY_DIR) + "/bin";
// Bounds a wait for something the node must do (hangs, not speed), ms.
constexpr int kWaitMs = 20000;

template <typename Done>
bool spin_until(Client& c, Done done) {
  for (int waited = 0; waited < kWaitMs && !done(); waited += 10) c.spin_once(10);
  return done();
}

class SecureBoard : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    std::string why;
    if (!load_cross_build(GetParam(), build_, why)) {
      GTEST_SKIP() << why;
    }
    // As a user sets one up: key pairs for the node and two clients, a
    // config naming the node's key and the one client it accepts (paths
    // relative to the config), compiled on the host for the board.
    dir_ = make_temp_dir("secure-" + build_.name);
    for (const char* name : {"node", "laptop", "stranger"}) {
      ASSERT_TRUE(wire::noise::write_key_pair(dir_ + "/" + name, name, why)) << why;
    }
    const std::string json = dir_ + "/secure.json";
    std::ofstream(json) << R"({ "name": "secure-board", "key": "node", "clients": [{ "key": "laptop.pub" }],
        "drivers": [{ "driver_type": "kinematic", "driver": { "rate_hz": 20 }, "provides": ["position2d:0"] }] })";
    std::string out;
    ASSERT_EQ(run(quote(kHostBin + "/troupe") + " config compile " + quote(json) + " --board " + build_.board +
                      " -o " + quote(dir_ + "/secure.bin") + " 2>&1",
                  out),
              0)
        << out;
    ASSERT_TRUE(node_.start(build_, build_.node, dir_ + "/secure.bin", why)) << why;
  }
  void TearDown() override {
    if (node_.running()) {
      EXPECT_EQ(node_.stop(), 0) << node_.log();
    }
    std::string ignored;
    if (!dir_.empty()) run("rm -rf " + quote(dir_), ignored);
  }

  // A client holding `identity`'s secret key and the node's public key.
  std::unique_ptr<Client> client_as(const std::string& identity) {
    Client::Options o;
    o.name = identity;
    o.reconnect = false;
    std::string error;
    wire::noise::ClientKeys keys{dir_ + "/" + identity, dir_ + "/node.pub"};
    o.transport = wire::noise::client_transport(keys, "127.0.0.1", node_.port(), error);
    EXPECT_NE(o.transport, nullptr) << error;
    return std::make_unique<Client>("127.0.0.1", node_.port(), o);
  }

  CrossBuild build_;
  QemuNode node_;
  std::string dir_;
};

TEST_P(SecureBoard, KnownClientCompletesTheHandshakeAndReadsADevice) {
  auto laptop = client_as("laptop");
  ASSERT_TRUE(laptop->connect(kWaitMs)) << laptop->error() << "\n" << node_.log();
  EXPECT_EQ(laptop->node_name(), "secure-board");
  EXPECT_TRUE(node_.wait_for_log("secure session with key ")) << node_.log();
  std::vector<client::DeviceEntry> devices;
  ASSERT_TRUE(laptop->device_list(devices)) << laptop->error();
  ASSERT_EQ(devices.size(), 1u);
  EXPECT_EQ(devices[0].text(), "position2d:0");

  // Data streams through the encrypted session, and a command reaches the
  // driver: the base follows it.
  Position2dProxy base(*laptop);
  ASSERT_TRUE(base.is_open()) << laptop->error();
  ASSERT_TRUE(base.set_odometry(-1.25f, 2.5f, 0.75f)) << laptop->error();
  EXPECT_TRUE(spin_until(*laptop, [&] { return base.x() == -1.25f; })) << base.x();
  EXPECT_FLOAT_EQ(base.y(), 2.5f);
}

TEST_P(SecureBoard, UnknownKeyIsRefusedWhileTheKnownClientIsServed) {
  auto laptop = client_as("laptop");
  ASSERT_TRUE(laptop->connect(kWaitMs)) << laptop->error() << "\n" << node_.log();
  size_t data = 0;
  laptop->add_data_handler([&](const wire::Message&) { ++data; });
  Position2dProxy base(*laptop);
  ASSERT_TRUE(base.is_open()) << laptop->error();
  ASSERT_TRUE(spin_until(*laptop, [&] { return data >= 3; }));

  auto stranger = client_as("stranger");
  EXPECT_FALSE(stranger->connect(kWaitMs));
  EXPECT_NE(stranger->error().find("during the secure handshake"), std::string::npos) << stranger->error();
  EXPECT_TRUE(node_.wait_for_log("is not among the node's clients")) << node_.log();

  // A plain client is refused as well.
  Client::Options plain_options;
  plain_options.reconnect = false;
  Client plain("127.0.0.1", node_.port(), plain_options);
  EXPECT_FALSE(plain.connect(kWaitMs));
  EXPECT_TRUE(node_.wait_for_log("did not open a secure session")) << node_.log();

  // The known client's session went on: more data, and requests answered.
  const size_t before = data;
  EXPECT_TRUE(spin_until(*laptop, [&] { return data >= before + 3; })) << node_.log();
  EXPECT_TRUE(laptop->sync()) << laptop->error();
  EXPECT_TRUE(laptop->connected());
}

INSTANTIATE_TEST_SUITE_P(Targets, SecureBoard,
                         ::testing::Values("ppc-node-armhf", "ppc-node-arm64-static", "ppc-node-powerpc"),
                         [](const auto& param_info) { return test_name_of(param_info.param); });

}  // namespace
}  // namespace troupe::cross
