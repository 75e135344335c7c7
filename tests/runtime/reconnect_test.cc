// A client notices a node that went away, reconnects when it is back,
// re-opens its devices; its proxies keep working.
#include <gtest/gtest.h>

#include "drivers/kinematic/kinematic.h"
#include "tests/runtime/node_fixture.h"
#include "wire/client/proxies.h"

namespace troupe::testing {
namespace {

using wire::Interface;

std::unique_ptr<NodeThread> kinematic_node(uint16_t port) {
  Node::Options options = test_options();
  options.port = port;
  auto n = std::make_unique<NodeThread>(options);
  n->add_device(Interface::Position2d, 0, new drivers::kinematic::Kinematic, "kinematic");
  n->start();
  return n;
}

TEST(Reconnect, ClientComesBackAfterTheNodeRestarts) {
  auto node = kinematic_node(0);
  uint16_t port = node->port();
  client::Client::Options options;
  options.reconnect_min_ms = 20;
  options.reconnect_max_ms = 200;
  client::Client c("127.0.0.1", port, options);
  ASSERT_TRUE(c.connect());
  client::Position2dProxy base(c);
  ASSERT_TRUE(base.is_open());
  for (int i = 0; i < 300 && base.samples() < 2; ++i) c.spin_once(10);
  ASSERT_GE(base.samples(), 2u);

  node.reset();  // the node goes away
  for (int i = 0; i < 300 && c.connected(); ++i) c.spin_once(10);
  ASSERT_FALSE(c.connected());
  uint64_t samples_before = base.samples();
  c.spin_for(100);  // a few failed attempts while nothing listens
  EXPECT_FALSE(c.connected());

  node = kinematic_node(port);  // back, fresh odometry
  for (int i = 0; i < 500 && (!c.connected() || base.samples() < samples_before + 2); ++i) c.spin_once(10);
  ASSERT_TRUE(c.connected()) << c.error();
  EXPECT_EQ(c.connections(), 2u);
  EXPECT_GE(base.samples(), samples_before + 2) << "the device was not re-opened";

  // Commands reach the new node through the same proxy.
  ASSERT_TRUE(base.set_velocity(0.5f, 0, 0));
  for (int i = 0; i < 500 && base.x() < 0.05f; ++i) c.spin_once(10);
  EXPECT_GT(base.x(), 0.05f);
}

TEST(Reconnect, ConnectToNothingFailsWithAClearError) {
  auto node = kinematic_node(0);
  uint16_t port = node->port();
  node.reset();
  client::Client::Options options;
  options.reconnect = false;
  client::Client c("127.0.0.1", port, options);
  EXPECT_FALSE(c.connect(1000));
  EXPECT_NE(c.error().find("Connection refused"), std::string::npos) << c.error();
  client::Client nowhere("no-such-host.invalid", port, options);
  EXPECT_FALSE(nowhere.connect(1000));
  EXPECT_NE(nowhere.error().find("cannot resolve host"), std::string::npos) << nowhere.error();
}

}  // namespace
}  // namespace troupe::testing
