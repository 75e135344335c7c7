// Player's semantics over loopback TCP: data to every reader, the newest
// command wins, exactly one reply per request within a deadline, Pull,
// device lists and access modes.
#include <gtest/gtest.h>

#include <thread>

#include "tests/runtime/node_fixture.h"
#include "wire/client/proxies.h"

namespace troupe::testing {
namespace {

using wire::Interface;
using wire::Kind;

TEST(Protocol, DeviceListNamesEveryDeviceAndDriver) {
  NodeThread n(test_options());
  n.add_device(Interface::Position2d, 0, new Recorder, "base");
  n.add_device(Interface::Ranger, 0, new Recorder, "sonar");
  n.add_device(Interface::Ranger, 1, new Recorder, "laser", 3);
  n.start();
  client::Client c("127.0.0.1", n.port());
  ASSERT_TRUE(c.connect()) << c.error();
  EXPECT_EQ(c.node_name(), "test-node");
  std::vector<client::DeviceEntry> list;
  ASSERT_TRUE(c.device_list(list)) << c.error();
  ASSERT_EQ(list.size(), 3u);
  EXPECT_EQ(list[0].text(), "position2d:0");
  EXPECT_EQ(list[0].driver, "base");
  EXPECT_EQ(list[1].text(), "ranger:0");
  EXPECT_EQ(list[2].text(), "3/ranger:1");
  EXPECT_EQ(list[2].driver, "laser");
}

TEST(Protocol, TwoClientsBothReceiveEverySample) {
  NodeThread n(test_options());
  auto* rec = new Recorder;
  n.add_device(Interface::Ranger, 0, rec);
  n.start();
  client::Client a("127.0.0.1", n.port()), b("127.0.0.1", n.port());
  ASSERT_TRUE(a.connect() && b.connect());
  client::RangerProxy ra(a), rb(b);
  ASSERT_TRUE(ra.is_open() && rb.is_open());
  rec->burst(1);  // one sample at a time: nobody falls behind
  for (int i = 0; i < 100 && (ra.samples() < 1 || rb.samples() < 1); ++i) {
    a.spin_once(10);
    b.spin_once(10);
  }
  ASSERT_EQ(ra.samples(), 1u);
  ASSERT_EQ(rb.samples(), 1u);
  EXPECT_EQ(ra.count(), 181u);
  EXPECT_FLOAT_EQ(ra.range(0), 1.0f);
  EXPECT_EQ(ra.seq(), rb.seq());
}

TEST(Protocol, NewerCommandInTheSameBatchReplacesTheOlder) {
  NodeThread n(test_options());
  auto* rec = new Recorder;
  n.add_device(Interface::Position2d, 0, rec);
  n.start();
  RawConnection raw(n.port());
  ASSERT_TRUE(raw.ok());
  ASSERT_FALSE(raw.read_until(Kind::Hello).empty());
  // Three commands in one write arrive in one read: the driver sees the last.
  std::vector<uint8_t> bytes;
  for (float vx : {0.1f, 0.2f, 0.3f}) {
    auto f = vel_frame(addr(Interface::Position2d), vx, 1);
    bytes.insert(bytes.end(), f.begin(), f.end());
  }
  ASSERT_TRUE(raw.send_bytes(bytes));
  auto sync = empty_frame({}, Kind::DeviceList, 0, 9);
  ASSERT_TRUE(raw.send_bytes(sync));
  ASSERT_FALSE(raw.read_until(Kind::DeviceList).empty());
  EXPECT_EQ(rec->commands.load(), 1);
  EXPECT_FLOAT_EQ(rec->last_vx.load(), 0.3f);
  // A command in a later read is delivered on its own.
  ASSERT_TRUE(raw.send_bytes(vel_frame(addr(Interface::Position2d), 0.5f, 2)));
  ASSERT_TRUE(raw.send_bytes(sync));
  ASSERT_FALSE(raw.read_until(Kind::DeviceList).empty());
  EXPECT_EQ(rec->commands.load(), 2);
  EXPECT_FLOAT_EQ(rec->last_vx.load(), 0.5f);
}

TEST(Protocol, RequestIsAnsweredOnceAndSilenceBecomesTimeout) {
  RecorderNode n(Interface::Position2d);
  Recorder* rec = n.recorder;
  client::Client& c = *n.client;
  auto pos = addr(Interface::Position2d);
  EXPECT_TRUE(c.request(pos, 4).ok());
  // The driver stays silent: the node answers Timeout at its deadline (300 ms).
  client::Reply silent = c.request(pos, Recorder::kNeverReply, wire::Body::NONE, 0, 5000);
  EXPECT_EQ(silent.status, client::Reply::Status::Nack);
  EXPECT_EQ(silent.code, wire::ErrorCode::Timeout);
  // A driver replying after the deadline: Timeout, and the late reply is dropped.
  client::Reply late = c.request(pos, Recorder::kReplyLate, wire::Body::NONE, 0, 5000);
  EXPECT_EQ(late.code, wire::ErrorCode::Timeout);
  // Listen long past the late reply (3x the deadline): exactly one reply,
  // the Nack, ever comes for the request.
  RawConnection raw(n.node.port());
  ASSERT_FALSE(raw.read_until(Kind::Hello).empty());
  ASSERT_TRUE(raw.send_bytes(empty_frame(pos, Kind::Request, Recorder::kReplyLate, 77)));
  std::vector<Kind> replies;
  for (auto f = raw.read_frame(1500); !f.empty(); f = raw.read_frame(1500)) {
    const wire::Message* m = wire::trusted_message(f);
    if (m->header()->seq() == 77) replies.push_back(m->header()->kind());
  }
  ASSERT_EQ(replies.size(), 1u);
  EXPECT_EQ(replies[0], Kind::Nack);
  EXPECT_EQ(rec->requests.load(), 4);
}

TEST(Protocol, RequestToAMissingDeviceIsRefusedByName) {
  RecorderNode n(Interface::Position2d);
  client::Client& c = *n.client;
  client::Reply r = c.request(addr(Interface::Ranger, 4), 1);
  EXPECT_EQ(r.status, client::Reply::Status::Nack);
  EXPECT_EQ(r.code, wire::ErrorCode::NoSuchDevice);
  EXPECT_NE(r.text.find("ranger:4"), std::string::npos);
  EXPECT_FALSE(c.open(addr(Interface::Ranger, 4)));
  EXPECT_TRUE(c.connected());  // a refusal does not end the session
}

TEST(Protocol, PullDeliversOnlyTheLatestSampleOnRequest) {
  RecorderNode n(Interface::Ranger);
  Recorder* rec = n.recorder;
  client::Client& c = *n.client;
  std::vector<uint32_t> seqs;
  c.add_data_handler([&](const wire::Message& m) { seqs.push_back(m.header()->seq()); });
  ASSERT_TRUE(c.open(addr(Interface::Ranger), wire::Access::Read, wire::Delivery::Pull));
  rec->burst(5);
  while (rec->published.load() < 5) c.spin_once(5);
  ASSERT_TRUE(c.sync());
  EXPECT_TRUE(seqs.empty()) << "pull-mode readers get nothing unasked";
  ASSERT_TRUE(c.pull(addr(Interface::Ranger)));
  ASSERT_EQ(seqs.size(), 1u);
  EXPECT_EQ(seqs[0], 5u);
}

// A device that compresses nothing publishes to every reader: one whose
// Open asked for PNG images gets the same frames, pushed or pulled (the
// simulator's per-packing frames are tested in tests/sim/camera_wire_test).
TEST(Protocol, AReaderAskingForPngGetsWhatADeviceThatPacksNothingSends) {
  RecorderNode n(Interface::Ranger);
  client::Client& raw = *n.client;
  client::Client push("127.0.0.1", n.node.port()), pull("127.0.0.1", n.node.port());
  ASSERT_TRUE(push.connect() && pull.connect());
  std::vector<uint32_t> raw_seqs, push_seqs, pull_seqs;
  raw.add_data_handler([&](const wire::Message& m) { raw_seqs.push_back(m.header()->seq()); });
  push.add_data_handler([&](const wire::Message& m) { push_seqs.push_back(m.header()->seq()); });
  pull.add_data_handler([&](const wire::Message& m) { pull_seqs.push_back(m.header()->seq()); });
  const auto ranger = addr(Interface::Ranger);
  ASSERT_TRUE(raw.open(ranger, wire::Access::Read));
  ASSERT_TRUE(push.open(ranger, wire::Access::Read, wire::Delivery::Push, wire::ImageCompression::Png));
  ASSERT_TRUE(pull.open(ranger, wire::Access::Read, wire::Delivery::Pull, wire::ImageCompression::Png));
  n.recorder->burst(1);
  while (n.recorder->published.load() < 1) raw.spin_once(5);
  ASSERT_TRUE(raw.sync() && push.sync() && pull.pull(ranger));
  EXPECT_EQ(raw_seqs, std::vector<uint32_t>{1});
  EXPECT_EQ(push_seqs, std::vector<uint32_t>{1});
  EXPECT_EQ(pull_seqs, std::vector<uint32_t>{1});
}

TEST(Protocol, ReadOnlyOpenRefusesCommands) {
  RecorderNode n(Interface::Position2d);
  Recorder* rec = n.recorder;
  client::Client& c = *n.client;
  auto pos = addr(Interface::Position2d);
  ASSERT_TRUE(c.open(pos, wire::Access::Read));
  auto& b = c.begin();
  wire::Pose2d vel(1, 0, 0);
  ASSERT_TRUE(c.command(pos, 1, wire::Body::Position2dVel, wire::CreatePosition2dVel(b, &vel).Union()));
  ASSERT_TRUE(c.sync());
  EXPECT_NE(c.error().find("read-only"), std::string::npos) << c.error();
  EXPECT_EQ(rec->commands.load(), 0);
  // Any client may still command it when it has not opened it read-only.
  client::Client other("127.0.0.1", n.node.port());
  ASSERT_TRUE(other.connect());
  auto& b2 = other.begin();
  ASSERT_TRUE(other.command(pos, 1, wire::Body::Position2dVel, wire::CreatePosition2dVel(b2, &vel).Union()));
  ASSERT_TRUE(other.sync());
  EXPECT_EQ(rec->commands.load(), 1);
}

// Pull is a one-shot read: it needs no Open (and the schema now says so).
TEST(Protocol, PullWorksWithoutOpen) {
  RecorderNode n(Interface::Ranger);
  n.recorder->burst(2);
  while (n.recorder->published.load() < 2) std::this_thread::yield();
  RawConnection raw(n.node.port());
  ASSERT_FALSE(raw.read_until(Kind::Hello).empty());
  ASSERT_TRUE(raw.send_bytes(empty_frame(addr(Interface::Ranger), Kind::Pull, 0, 31)));
  auto data = raw.read_frame();
  ASSERT_FALSE(data.empty());
  EXPECT_EQ(wire::trusted_message(data)->header()->kind(), Kind::Data);
  EXPECT_EQ(wire::trusted_message(data)->header()->seq(), 2u);  // the device's newest sample
  auto ack = raw.read_frame();
  ASSERT_FALSE(ack.empty());
  EXPECT_EQ(wire::trusted_message(ack)->header()->kind(), Kind::Ack);
  EXPECT_EQ(wire::trusted_message(ack)->header()->seq(), 31u);
}

// Every reply carries the seq, the subtype and the address of what it
// answers (the device list and time sync replies sent subtype 0).
TEST(Protocol, RepliesEchoSeqSubtypeAndAddress) {
  RecorderNode n(Interface::Ranger);
  RawConnection raw(n.node.port());
  ASSERT_FALSE(raw.read_until(Kind::Hello).empty());
  const wire::Address some(2, 0, 7);
  ASSERT_TRUE(raw.send_bytes(empty_frame(some, Kind::DeviceList, 9, 77)));
  auto list = raw.read_until(Kind::DeviceList);
  ASSERT_FALSE(list.empty());
  const wire::Header* h = wire::trusted_message(list)->header();
  EXPECT_EQ(h->seq(), 77u);
  EXPECT_EQ(h->subtype(), 9);
  EXPECT_TRUE(h->addr() == some);
  wire::MessageWriter w;
  auto& b = w.start();
  auto body = wire::CreateTimeSync(b, 123);
  ASSERT_TRUE(raw.send_bytes(w.finish(wire::make_header(some, Kind::TimeSync, 3, 78, 0), wire::Body::TimeSync,
                                      body.Union())));
  auto sync = raw.read_until(Kind::TimeSync);
  ASSERT_FALSE(sync.empty());
  h = wire::trusted_message(sync)->header();
  EXPECT_EQ(h->seq(), 78u);
  EXPECT_EQ(h->subtype(), 3);
  EXPECT_EQ(wire::trusted_message(sync)->body_as_TimeSync()->client_send_us(), 123u);
  ASSERT_TRUE(raw.send_bytes(empty_frame(addr(Interface::Ranger), Kind::Request, 1, 79)));
  auto ack = raw.read_until(Kind::Ack);
  ASSERT_FALSE(ack.empty());
  EXPECT_EQ(wire::trusted_message(ack)->header()->seq(), 79u);
  EXPECT_EQ(wire::trusted_message(ack)->header()->subtype(), 1);
}

std::vector<uint8_t> hello_frame(uint32_t max_frame_bytes) {
  wire::MessageWriter w;
  auto& b = w.start();
  auto body = wire::CreateHello(b, wire::kProtocolVersion, b.CreateString("small"), max_frame_bytes);
  auto f = w.finish(wire::make_header({}, Kind::Hello, 0, 0, 0), wire::Body::Hello, body.Union());
  return {f.begin(), f.end()};
}

// A client's Hello.max_frame_bytes is honoured: a reply larger than it is
// answered Nack TooLarge instead (it used to be ignored).
TEST(Protocol, TheClientsFrameLimitIsHonoured) {
  NodeThread node(test_options());
  node.add_device(Interface::Ranger, 0, new Recorder, std::string(2000, 'x').c_str());
  node.start();
  RawConnection raw(node.port());
  ASSERT_FALSE(raw.read_until(Kind::Hello).empty());
  ASSERT_TRUE(raw.send_bytes(hello_frame(1024)));
  ASSERT_TRUE(raw.send_bytes(empty_frame({}, Kind::DeviceList, 0, 5)));
  auto nack = raw.read_frame();
  ASSERT_FALSE(nack.empty());
  const wire::Message* m = wire::trusted_message(nack);
  ASSERT_EQ(m->header()->kind(), Kind::Nack);
  EXPECT_EQ(m->header()->seq(), 5u);
  EXPECT_EQ(m->body_as_Error()->code(), wire::ErrorCode::TooLarge);
  // Small replies still come.
  ASSERT_TRUE(raw.send_bytes(empty_frame(addr(Interface::Ranger), Kind::Request, 1, 6)));
  EXPECT_FALSE(raw.read_until(Kind::Ack).empty());
  // A limit too small for any reply is refused.
  RawConnection tiny(node.port());
  ASSERT_FALSE(tiny.read_until(Kind::Hello).empty());
  ASSERT_TRUE(tiny.send_bytes(hello_frame(100)));
  auto e = tiny.read_until(Kind::Error);
  ASSERT_FALSE(e.empty());
  EXPECT_EQ(wire::trusted_message(e)->body_as_Error()->code(), wire::ErrorCode::BadValue);
  EXPECT_TRUE(tiny.wait_closed());
}

TEST(Protocol, ClockOffsetIsLearnedAtConnect) {
  RecorderNode n(Interface::Position2d);
  client::Client& c = *n.client;
  ASSERT_TRUE(c.sync());
  // Same machine, same monotonic clock: the offset is the round trip's
  // asymmetry, far below a second.
  EXPECT_LT(std::abs(c.clock_offset_us()), 1'000'000);
}

}  // namespace
}  // namespace troupe::testing
