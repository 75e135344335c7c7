// localhost as a standard Debian 12 resolves it: /etc/hosts gives ::1 and
// 127.0.0.1, and getaddrinfo returns ::1 first. Clients try every address in
// order, a node's default listen serves both loopbacks, and a node listening
// on IPv6 only is reached. Real nodes, real sockets; only the hosts file is
// the test's own (hosts_resolver.h), since this machine's may differ.
#include <gtest/gtest.h>
#include <unistd.h>

#include "drivers/kinematic/kinematic.h"
#include "tests/runtime/node_fixture.h"
#include "tests/wire/hosts_resolver.h"
#include "wire/record/log_file.h"
#include "wire/record/recorder.h"

namespace troupe::testing {
namespace {

using wire::Interface;

std::unique_ptr<NodeThread> kinematic_node(const std::string& listen) {
  Node::Options options = test_options();
  options.listen = listen;
  auto n = std::make_unique<NodeThread>(options);
  n->add_device(Interface::Position2d, 0, new drivers::kinematic::Kinematic, "kinematic");
  n->start();
  return n;
}

client::Client::Options debian_localhost() {
  client::Client::Options o;
  o.reconnect = false;
  o.resolver = hosts_resolver(kDebianHosts);
  return o;
}

bool lists_the_base(client::Client& c) {
  std::vector<client::DeviceEntry> devices;
  return c.device_list(devices) && devices.size() == 1 && devices[0].text() == "position2d:0";
}

TEST(Localhost, V6FirstStillReachesANodeOnV4Only) {
  auto node = kinematic_node("127.0.0.1");
  client::Client c("localhost", node->port(), debian_localhost());
  ASSERT_TRUE(c.connect(3000)) << c.error();
  EXPECT_TRUE(lists_the_base(c)) << c.error();
}

TEST(Localhost, TheDefaultListenServesBothLoopbacks) {
  EXPECT_EQ(Node::Options{}.listen, "localhost");
  auto node = kinematic_node("localhost");
  for (const char* host : {"::1", "127.0.0.1"}) {
    SCOPED_TRACE(host);
    client::Client c(host, node->port(), debian_localhost());
    ASSERT_TRUE(c.connect(3000)) << c.error();
    EXPECT_TRUE(lists_the_base(c)) << c.error();
  }
}

TEST(Localhost, ANodeListeningOnV6IsReached) {
  for (const char* listen : {"::1", "[::1]"}) {
    SCOPED_TRACE(listen);
    auto node = kinematic_node(listen);
    client::Client by_address("::1", node->port(), debian_localhost());
    ASSERT_TRUE(by_address.connect(3000)) << by_address.error();
    EXPECT_TRUE(lists_the_base(by_address)) << by_address.error();
    client::Client by_name("localhost", node->port(), debian_localhost());
    ASSERT_TRUE(by_name.connect(3000)) << by_name.error();
    client::Client v4("127.0.0.1", node->port(), debian_localhost());
    EXPECT_FALSE(v4.connect(3000));
    EXPECT_EQ(v4.error(), "cannot connect to 127.0.0.1:" + std::to_string(node->port()) + ": Connection refused");
  }
}

TEST(Localhost, NothingListeningNamesEveryAddressTried) {
  auto node = kinematic_node("127.0.0.1");
  uint16_t port = node->port();
  node.reset();
  client::Client c("localhost", port, debian_localhost());
  EXPECT_FALSE(c.connect(3000));
  EXPECT_EQ(c.error(), "cannot connect to localhost:" + std::to_string(port) + ": Connection refused");
}

TEST(Localhost, TheRecorderFallsBackToo) {
  auto node = kinematic_node("127.0.0.1");
  char dir[] = TROUPE_BINARY_DIR "/tests/wire/localhostXXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  record::RecordOptions o;
  o.host = "localhost";
  o.port = node->port();
  o.devices = {"position2d:0"};
  o.output = std::string(dir) + "/base.trl";
  o.max_frames = 3;
  o.resolver = hosts_resolver(kDebianHosts);
  record::Recorder recorder(o);
  std::string error;
  ASSERT_TRUE(recorder.start(error)) << error;
  ASSERT_TRUE(recorder.run(-1, error)) << error;
  EXPECT_EQ(recorder.frames(), 3u);
  record::LogSummary summary;
  ASSERT_TRUE(record::summarize_log(o.output, summary, error)) << error;
  EXPECT_EQ(summary.data_records, 3u);
  EXPECT_EQ(summary.node_name, "test-node");
  unlink(o.output.c_str());
  rmdir(dir);
}

}  // namespace
}  // namespace troupe::testing
