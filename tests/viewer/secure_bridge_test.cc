// The viewer's bridge to a secure troupe-node (a real process, its keys made
// by `troupe keygen`): the bridge runs the Noise session on its TCP side
// with the viewer's identity, and a WebSocket client speaking the wire as
// the page does reads the node's device list and data in plain frames. With
// a node key that is not the node's, the page's WebSocket is closed with
// the reason and nothing of the node reaches it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "host-sim/viewer/view_server.h"
#include "tests/support/secure_node.h"
#include "tests/viewer/page.h"
#include "wire/writer.h"

namespace troupe::viewer {
namespace {

class SecureBridge : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    ASSERT_TRUE(robot_.make_keys({"laptop"}, error)) << error;
    ASSERT_TRUE(robot_.start(R"([{ "key": "laptop.pub" }])", testing::kKinematicBase, error)) << error;
  }
  // The viewer on a free port, bridged to the robot as laptop holding `node_key`.
  void start_viewer(const std::string& node_key) {
    std::ofstream(robot_.path("index.html")) << "<title>the page</title>";
    ViewOptions vo;
    vo.http_port = 0;
    vo.node_port = robot_.port();
    vo.web_root = robot_.dir();
    vo.keys = {robot_.path("laptop"), robot_.path(node_key)};
    server_ = std::make_unique<ViewServer>(vo);
    std::string error;
    ASSERT_TRUE(server_->open(error)) << error;
    server_->start_thread();
  }
  void TearDown() override { server_.reset(); }

  std::span<const uint8_t> hello() {
    auto& b = w_.start();
    auto body = wire::CreateHello(b, wire::kProtocolVersion, b.CreateString("secure-bridge-test"), 1u << 20);
    return w_.finish(wire::make_header({}, wire::Kind::Hello, 0, 0, 0), wire::Body::Hello, body.Union());
  }

  testing::SecureNodeProcess robot_;
  std::unique_ptr<ViewServer> server_;
  wire::MessageWriter w_;
};

TEST_F(SecureBridge, APagesWebSocketReachesASecureNodeInPlainFrames) {
  start_viewer("node.pub");
  Page page(server_->port());
  page.send(hello());
  w_.start();
  page.send(w_.finish(wire::make_header({}, wire::Kind::DeviceList, 0, 1, 0)));
  const std::vector<uint8_t> list = page.reply(1);
  ASSERT_FALSE(list.empty()) << reason(page);
  const wire::DeviceList* devices = wire::trusted_message(list)->body_as_DeviceList();
  ASSERT_NE(devices, nullptr);
  ASSERT_EQ(devices->devices()->size(), 1u);
  EXPECT_EQ(devices->devices()->Get(0)->addr()->iface(), uint16_t(wire::Interface::Position2d));

  const wire::Address pos{0, uint16_t(wire::Interface::Position2d), 0};
  auto& b = w_.start();
  auto open = wire::CreateOpen(b, wire::Access::Read);
  page.send(w_.finish(wire::make_header(pos, wire::Kind::Open, 0, 2, 0), wire::Body::Open, open.Union()));
  ASSERT_FALSE(page.reply(2).empty()) << reason(page);
  EXPECT_FALSE(page.data(wire::Body::Position2dState).empty()) << "no data through the secure bridge";
  EXPECT_TRUE(robot_.node().wait_for("secure session with key ", true, 10'000)) << robot_.node().err();
}

TEST_F(SecureBridge, AWrongNodeKeyClosesThePagesWebSocketSayingWhy) {
  // laptop.pub is not the node's key.
  start_viewer("laptop.pub");
  Page page(server_->port());
  page.send(hello());
  std::optional<std::vector<uint8_t>> first = page.read();
  EXPECT_FALSE(first.has_value()) << "nothing of the node may reach the page";
  EXPECT_EQ(page.close_reason().code, boost::beast::websocket::close_code::policy_error);
  EXPECT_NE(reason(page).find("the node refused the secure session"), std::string::npos) << reason(page);
  EXPECT_TRUE(robot_.node().wait_for("does not hold this node's public key", true, 10'000))
      << robot_.node().err();
}

TEST_F(SecureBridge, AnUnreadableIdentityStopsTheViewerAtOpen) {
  ViewOptions vo;
  vo.http_port = 0;
  vo.node_port = robot_.port();
  vo.keys = {robot_.path("nobody"), robot_.path("node.pub")};
  ViewServer server(vo);
  std::string error;
  EXPECT_FALSE(server.open(error));
  EXPECT_NE(error.find(robot_.path("nobody")), std::string::npos) << error;
}

// troupe-sim with --secure serves its viewer as one of its clients: the
// bridge connects with --view-identity and the simulator's own key, and a
// page reads the simulated robot's devices. Without an identity of its own
// a secure simulator's viewer cannot connect: --view then stops it at start.
TEST_F(SecureBridge, ASecureSimulatorsViewerConnectsWithItsViewIdentity) {
  const std::string bin = std::string(TROUPE_BINARY_DIR) + "/bin/troupe-sim";
  std::ofstream(robot_.path("keys.json")) << R"({ "key": "node", "clients": [ { "key": "laptop.pub" } ] })";
  std::ofstream(robot_.path("one.world")) << "define bot position ( size [0.4 0.3] )\nbot ( name \"r0\" )\n";
  const std::vector<std::string> common = {bin,        robot_.path("one.world"), "--port", "0", "--view", "0",
                                           "--secure", robot_.path("keys.json")};

  testing::ProgramResult lonely = testing::run_to_end(common, 30'000);
  EXPECT_EQ(lonely.status, 1);
  EXPECT_NE(lonely.err.find("--view with --secure needs --view-identity FILE"), std::string::npos)
      << lonely.err;

  std::vector<std::string> argv = common;
  argv.insert(argv.end(), {"--view-identity", robot_.path("laptop")});
  testing::ChildProcess sim;
  std::string error;
  ASSERT_TRUE(sim.start(argv, robot_.dir(), "sim", error)) << error;
  ASSERT_TRUE(sim.wait_for("viewer at http://", false, 30'000)) << sim.err();
  const std::string out = sim.out();
  const size_t at = out.find(':', out.find("viewer at http://") + 17);
  Page page(uint16_t(std::atoi(out.c_str() + at + 1)));
  page.send(hello());
  w_.start();
  page.send(w_.finish(wire::make_header({}, wire::Kind::DeviceList, 0, 1, 0)));
  const std::vector<uint8_t> list = page.reply(1);
  ASSERT_FALSE(list.empty()) << reason(page) << sim.err();
  const wire::DeviceList* devices = wire::trusted_message(list)->body_as_DeviceList();
  ASSERT_NE(devices, nullptr);
  bool base = false;
  for (const wire::DeviceInfo* d : *devices->devices()) {
    base |= d->robot_name() && d->robot_name()->str() == "r0" &&
            d->addr()->iface() == uint16_t(wire::Interface::Position2d);
  }
  EXPECT_TRUE(base) << "r0/position2d:0 through the secure viewer";
  EXPECT_TRUE(sim.wait_for("secure session with key ", true, 10'000)) << sim.err();
  sim.kill_hard();
}

}  // namespace
}  // namespace troupe::viewer
