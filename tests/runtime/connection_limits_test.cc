// Client slots are bounded; connections that hold one without using it give
// it up. 64 connections that never said a word once locked every client out
// for good.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <thread>

#include "tests/runtime/node_fixture.h"

namespace troupe::testing {
namespace {

using wire::ErrorCode;
using wire::Interface;
using wire::Kind;

// Connections that connect and never send; each has read the node's Hello,
// so the node has accepted it.
std::vector<std::unique_ptr<RawConnection>> idle_connections(uint16_t port, int n) {
  std::vector<std::unique_ptr<RawConnection>> out;
  for (int i = 0; i < n; ++i) {
    out.push_back(std::make_unique<RawConnection>(port));
    EXPECT_FALSE(out.back()->read_until(Kind::Hello).empty()) << "connection " << i;
  }
  return out;
}

// A node whose ranger publishes a 181-beam scan every millisecond.
struct StreamingRanger {
  explicit StreamingRanger(const Node::Options& options) : node(options), ranger(new Recorder) {
    node.add_device(Interface::Ranger, 0, ranger);
    node.start();
    ranger->stream(1);
  }
  ~StreamingRanger() { ranger->stream(0); }
  uint16_t port() const { return node.port(); }
  NodeThread node;
  Recorder* ranger;  // owned by the node
};

// A reader of the ranger's stream, through a 1 KiB receive buffer, that
// stops reading once its Open is acknowledged.
std::unique_ptr<RawConnection> stalled_reader(uint16_t port) {
  auto r = std::make_unique<RawConnection>(port, 1024);
  EXPECT_FALSE(r->read_until(Kind::Hello).empty());
  EXPECT_TRUE(r->send_bytes(empty_frame(addr(Interface::Ranger), Kind::Open, 0, 1)));
  EXPECT_FALSE(r->read_until(Kind::Ack).empty());
  return r;
}

// Descriptors this process holds: the node runs in it, so a connection the
// node closes shows here before its peer reads anything.
size_t open_descriptors() {
  return size_t(std::distance(std::filesystem::directory_iterator("/proc/self/fd"),
                              std::filesystem::directory_iterator{}));
}

// Bounds a wait on the node's own clock (its sweep, the stall it measures);
// not a requirement.
constexpr auto kPatience = std::chrono::seconds(20);

ErrorCode error_code(RawConnection& raw) {
  auto f = raw.read_until(Kind::Error);
  return f.empty() ? ErrorCode::Unknown : wire::trusted_message(f)->body_as_Error()->code();
}

TEST(ConnectionLimits, SixtyFourIdleConnectionsDoNotLockAClientOut) {
  Node::Options o = test_options();
  o.hello_timeout_ms = 0;  // no deadline: the slots must be found without one
  NodeThread node(o);
  node.add_device(Interface::Position2d, 0, new Recorder);
  node.start();
  ASSERT_EQ(o.max_clients, 64);
  auto idle = idle_connections(node.port(), 64);
  client::Client c("127.0.0.1", node.port());
  ASSERT_TRUE(c.connect()) << c.error();
  std::vector<client::DeviceEntry> list;
  EXPECT_TRUE(c.device_list(list)) << c.error();
  // The oldest silent connection made room, and was told why.
  EXPECT_EQ(error_code(*idle.front()), ErrorCode::Timeout);
  EXPECT_TRUE(idle.front()->wait_closed());
  // And again: silent connections keep giving way to clients that speak.
  client::Client d("127.0.0.1", node.port());
  ASSERT_TRUE(d.connect()) << d.error();
  EXPECT_TRUE(d.sync());
  EXPECT_TRUE(c.sync());
}

TEST(ConnectionLimits, ClientsThatSpokeAreNeverEvicted) {
  Node::Options o = test_options();
  o.max_clients = 2;
  NodeThread node(o);
  node.add_device(Interface::Position2d, 0, new Recorder);
  node.start();
  client::Client a("127.0.0.1", node.port()), b("127.0.0.1", node.port());
  ASSERT_TRUE(a.connect() && b.connect());
  RawConnection third(node.port());
  EXPECT_EQ(error_code(third), ErrorCode::Denied);
  EXPECT_TRUE(third.wait_closed());
  EXPECT_TRUE(a.sync());
  EXPECT_TRUE(b.sync());
}

// 800 readers that never read once took every slot of a node for as long as
// they stayed connected: they had spoken, so they were never evicted.
TEST(ConnectionLimits, AReaderThatStopsReadingGivesUpItsSlotAndOneThatSpokeKeepsIt) {
  Node::Options o = test_options();
  o.max_clients = 2;
  o.hello_timeout_ms = 0;
  StreamingRanger node(o);
  auto stalled = stalled_reader(node.port());
  client::Client spoke("127.0.0.1", node.port());
  ASSERT_TRUE(spoke.connect()) << spoke.error();
  // Refused while the reader's socket still takes data, let in once it has
  // taken nothing for a while: the node measures that, the test only waits.
  client::Client late("127.0.0.1", node.port());
  const auto give_up = std::chrono::steady_clock::now() + kPatience;
  bool in = false;
  while (!(in = late.connect()) && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_TRUE(in) << late.error();
  EXPECT_TRUE(stalled->wait_closed()) << "the stalled reader kept its slot";
  EXPECT_TRUE(spoke.sync()) << "a client that spoke and had nothing to read was evicted";
  EXPECT_TRUE(late.sync());
}

TEST(ConnectionLimits, AReaderThatTakesNoDataIsClosedAtTheIdleDeadline) {
  Node::Options o = test_options();
  o.idle_timeout_ms = 300;
  StreamingRanger node(o);
  const size_t before = open_descriptors();
  auto stalled = stalled_reader(node.port());
  ASSERT_EQ(open_descriptors(), before + 2);  // both ends
  // Not a byte read meanwhile: reading would end the stall.
  const auto give_up = std::chrono::steady_clock::now() + kPatience;
  while (open_descriptors() > before + 1 && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_EQ(open_descriptors(), before + 1) << "the node kept a reader that took no data";
  EXPECT_TRUE(stalled->wait_closed());
}

TEST(ConnectionLimits, ASilentConnectionIsClosedAtTheHelloDeadline) {
  Node::Options o = test_options();
  o.hello_timeout_ms = 200;
  NodeThread node(o);
  node.add_device(Interface::Position2d, 0, new Recorder);
  node.start();
  auto idle = idle_connections(node.port(), 3);
  for (auto& raw : idle) {
    EXPECT_EQ(error_code(*raw), ErrorCode::Timeout);
    EXPECT_TRUE(raw->wait_closed());
  }
  // A connection whose first frame is anything valid has greeted: a client
  // need not send Hello.
  RawConnection raw(node.port());
  ASSERT_FALSE(raw.read_until(Kind::Hello).empty());
  ASSERT_TRUE(raw.send_bytes(empty_frame({}, Kind::DeviceList, 0, 1)));
  ASSERT_FALSE(raw.read_until(Kind::DeviceList).empty());
  ASSERT_TRUE(raw.send_bytes(empty_frame(addr(Interface::Position2d), Kind::Open, 0, 2)));
  ASSERT_FALSE(raw.read_until(Kind::Ack).empty());
  EXPECT_TRUE(raw.read_until(Kind::Error, 600).empty()) << "a client that spoke was closed";
}

TEST(ConnectionLimits, SilentNonReadersAreClosedAtTheIdleDeadlineAndReadersStay) {
  Node::Options o = test_options();
  o.idle_timeout_ms = 300;
  NodeThread node(o);
  node.add_device(Interface::Position2d, 0, new Recorder);
  node.start();
  RawConnection silent(node.port()), reader(node.port());
  for (RawConnection* r : {&silent, &reader}) {
    ASSERT_FALSE(r->read_until(Kind::Hello).empty());
    ASSERT_TRUE(r->send_bytes(empty_frame({}, Kind::DeviceList, 0, 1)));
    ASSERT_FALSE(r->read_until(Kind::DeviceList).empty());
  }
  ASSERT_TRUE(reader.send_bytes(empty_frame(addr(Interface::Position2d), Kind::Open, 0, 2)));
  ASSERT_FALSE(reader.read_until(Kind::Ack).empty());
  auto f = silent.read_until(Kind::Error, 3000);
  ASSERT_FALSE(f.empty());
  EXPECT_EQ(wire::trusted_message(f)->body_as_Error()->code(), ErrorCode::Timeout);
  EXPECT_NE(wire::trusted_message(f)->body_as_Error()->text()->str().find("silent"), std::string::npos);
  EXPECT_TRUE(silent.wait_closed());
  EXPECT_TRUE(reader.read_until(Kind::Error, 600).empty()) << "a reader was closed";
  ASSERT_TRUE(reader.send_bytes(empty_frame({}, Kind::DeviceList, 0, 3)));
  EXPECT_FALSE(reader.read_until(Kind::DeviceList).empty());
}

TEST(ConnectionLimits, OneAddressTakesAtMostItsShare) {
  Node::Options o = test_options();
  o.max_clients_per_address = 2;
  o.hello_timeout_ms = 0;
  NodeThread node(o);
  node.add_device(Interface::Position2d, 0, new Recorder);
  node.start();
  client::Client a("127.0.0.1", node.port());
  ASSERT_TRUE(a.connect());
  auto idle = idle_connections(node.port(), 1);
  // The address is at its limit: the silent one makes room for a client.
  client::Client b("127.0.0.1", node.port());
  ASSERT_TRUE(b.connect()) << b.error();
  EXPECT_EQ(error_code(*idle.front()), ErrorCode::Timeout);
  // Both slots of the address serve clients that spoke: a third is refused
  // although the node has 62 free.
  RawConnection third(node.port());
  EXPECT_EQ(error_code(third), ErrorCode::Denied);
  EXPECT_TRUE(a.sync() && b.sync());
}

}  // namespace
}  // namespace troupe::testing
