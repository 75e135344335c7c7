// The connection core driven byte by byte with time as plain numbers: no
// sockets, no clock. The test plays the adapter (answering actions) and the
// node (writing its frames into the connection, reading what it sends).
#include "wire/connection/connection.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "wire/connection/transport.h"

namespace troupe::wire {
namespace {

using Bytes = std::vector<uint8_t>;
constexpr uint64_t kMs = 1000;

Bytes bytes(std::span<const uint8_t> s) {
  return Bytes(s.begin(), s.end());
}

Bytes node_hello(uint16_t version = kProtocolVersion, const char* name = "robot7") {
  MessageWriter w;
  auto& b = w.start();
  auto hello = CreateHello(b, version, b.CreateString(name), 1u << 20, 0, 42);
  return bytes(w.finish(make_header({}, Kind::Hello, 0, 0, 42), Body::Hello, hello.Union()));
}

Bytes data(uint32_t seq) {
  MessageWriter w;
  auto& b = w.start();
  Pose2d pose(float(seq), 0, 0);
  auto body = CreatePosition2dState(b, &pose);
  return bytes(w.finish(make_header(Address(0, uint16_t(Interface::Position2d), 0), Kind::Data, 0, seq, seq),
                        Body::Position2dState, body.Union()));
}

Bytes time_sync_reply(uint32_t seq, uint64_t client_send, uint64_t node_recv, uint64_t node_send) {
  MessageWriter w;
  auto& b = w.start();
  auto body = CreateTimeSync(b, client_send, node_recv, node_send);
  return bytes(w.finish(make_header({}, Kind::TimeSync, 0, seq, node_send), Body::TimeSync, body.Union()));
}

Bytes node_error(const char* text) {
  MessageWriter w;
  auto& b = w.start();
  auto body = CreateError(b, ErrorCode::Denied, b.CreateString(text));
  return bytes(w.finish(make_header({}, Kind::Error, 0, 0, 0), Body::Error, body.Union()));
}

Bytes join(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const Bytes& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

/// Writes `in` into the connection `chunk` bytes at a time, as reads would.
void feed(Connection& c, uint64_t now, const Bytes& in, size_t chunk = SIZE_MAX) {
  for (size_t at = 0; at < in.size();) {
    size_t n = std::min(chunk, in.size() - at);
    std::span<uint8_t> space = c.read_space(n);
    std::memcpy(space.data(), in.data() + at, n);
    c.received(now, n);
    at += n;
  }
}

/// Everything the connection wants written, as the frames it holds.
std::vector<Bytes> sent(Connection& c) {
  Bytes out = bytes(c.output());
  c.consumed(out.size());
  FrameReader reader(1u << 20);
  std::span<uint8_t> space = reader.write_space(out.size());
  std::copy(out.begin(), out.end(), space.begin());
  reader.commit(out.size());
  std::vector<Bytes> frames;
  for (auto f = reader.next(); !f.empty(); f = reader.next()) frames.push_back(bytes(f));
  EXPECT_EQ(reader.pending_bytes(), 0u);
  return frames;
}

const Message& msg(const Bytes& frame) {
  const Message* m = verify_frame(frame, Limits{});
  EXPECT_NE(m, nullptr);
  return *m;
}

std::vector<Action> actions(Connection& c) {
  std::vector<Action> out;
  for (Action a = c.next_action(); a.kind != ActionKind::None; a = c.next_action()) out.push_back(a);
  return out;
}

bool is(const Action& a, ActionKind kind, uint32_t candidate = 0) {
  return a.kind == kind && a.candidate == candidate;
}

ConnectionOptions options() {
  ConnectionOptions o;
  o.name = "test-client";
  o.target = "localhost:6665";
  return o;
}

/// A connection whose first address answered at `now`: Handshake, with its
/// Hello and TimeSync taken.
void connect(Connection& c, uint64_t now, std::vector<std::string> candidates = {"127.0.0.1:6665"}) {
  c.start(now);
  ASSERT_TRUE(is(c.next_action(), ActionKind::Resolve));
  c.resolved(now, std::move(candidates));
  ASSERT_TRUE(is(c.next_action(), ActionKind::Connect, 0));
  c.attempt_connected(now, 0);
  actions(c);
  ASSERT_EQ(c.state(), LinkState::Handshake);
}

void up(Connection& c, uint64_t now) {
  connect(c, now);
  sent(c);
  feed(c, now, node_hello());
  ASSERT_EQ(c.next_event().kind, EventKind::Up);
}

TEST(Connection, StartsByResolvingThenTriesTheFirstAddress) {
  Connection c(options());
  EXPECT_EQ(c.state(), LinkState::Idle);
  EXPECT_EQ(c.next_deadline_us(), kNoDeadline);
  c.start(1000);
  EXPECT_EQ(c.state(), LinkState::Connecting);
  EXPECT_TRUE(is(c.next_action(), ActionKind::Resolve));
  EXPECT_EQ(c.next_action().kind, ActionKind::None);
  c.resolved(1000, {"[::1]:6665", "127.0.0.1:6665"});
  std::vector<Action> a = actions(c);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_TRUE(is(a[0], ActionKind::Connect, 0));
  EXPECT_TRUE(c.output().empty());
  EXPECT_EQ(c.next_deadline_us(), 1000 + 250 * kMs) << "RFC 8305's attempt delay";
}

TEST(Connection, LocalhostWithV6RefusedFallsBackToV4AtOnce) {
  // A standard Debian 12: localhost is ::1 first, the node listens on 127.0.0.1.
  Connection c(options());
  c.start(0);
  actions(c);
  c.resolved(0, {"[::1]:6665", "127.0.0.1:6665"});
  actions(c);
  c.attempt_failed(10, 0, "Connection refused");
  std::vector<Action> a = actions(c);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_TRUE(is(a[0], ActionKind::Connect, 1)) << "a failed address starts the next without waiting";
  EXPECT_EQ(c.next_event().kind, EventKind::None);
  c.attempt_connected(20, 1);
  EXPECT_EQ(c.state(), LinkState::Handshake);

  std::vector<Bytes> out = sent(c);
  ASSERT_EQ(out.size(), 2u);
  const Message& hello = msg(out[0]);
  ASSERT_EQ(hello.header()->kind(), Kind::Hello);
  EXPECT_EQ(hello.body_as_Hello()->protocol_version(), kProtocolVersion);
  EXPECT_EQ(hello.body_as_Hello()->name()->str(), "test-client");
  EXPECT_EQ(hello.body_as_Hello()->clock_us(), 20u);
  EXPECT_EQ(msg(out[1]).header()->kind(), Kind::TimeSync);
}

TEST(Connection, AnAddressThatHangsIsJoinedByTheNextAfterTheAttemptDelay) {
  Connection c(options());
  c.start(0);
  actions(c);
  c.resolved(0, {"[2001:db8::1]:6665", "192.0.2.1:6665"});
  actions(c);
  c.tick(250 * kMs - 1);
  EXPECT_TRUE(actions(c).empty());
  c.tick(250 * kMs);
  std::vector<Action> a = actions(c);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_TRUE(is(a[0], ActionKind::Connect, 1));
  // Both race; the second wins and the first is abandoned.
  c.attempt_connected(300 * kMs, 1);
  a = actions(c);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_TRUE(is(a[0], ActionKind::Abandon, 0));
  // The loser reporting late changes nothing but gets closed.
  c.attempt_connected(301 * kMs, 0);
  a = actions(c);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_TRUE(is(a[0], ActionKind::Abandon, 0));
  EXPECT_EQ(c.state(), LinkState::Handshake);
}

TEST(Connection, NoMoreThanTwoAttemptsAtOnce) {
  Connection c(options());
  c.start(0);
  actions(c);
  c.resolved(0, {"a", "b", "c"});
  actions(c);
  c.tick(250 * kMs);
  EXPECT_EQ(actions(c).size(), 1u);
  c.tick(500 * kMs);
  EXPECT_TRUE(actions(c).empty()) << "two in flight: the third waits";
  c.attempt_failed(600 * kMs, 0, "Network is unreachable");
  std::vector<Action> a = actions(c);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_TRUE(is(a[0], ActionKind::Connect, 2));
}

TEST(Connection, EveryAddressFailingReportsEachAndBacksOff) {
  ConnectionOptions o = options();
  o.backoff_min_us = 100 * kMs;
  o.backoff_max_us = 350 * kMs;
  Connection c(o);
  c.start(0);
  actions(c);
  c.resolved(0, {"[::1]:6665", "127.0.0.1:6665"});
  actions(c);
  c.attempt_failed(1, 0, "Cannot assign requested address");
  actions(c);
  c.attempt_failed(2, 1, "Connection refused");
  Event down = c.next_event();
  ASSERT_EQ(down.kind, EventKind::Down);
  EXPECT_EQ(down.text,
            "cannot connect to localhost:6665: [::1]:6665: Cannot assign requested address; 127.0.0.1:6665: "
            "Connection refused");
  EXPECT_EQ(c.state(), LinkState::Waiting);

  // The waits double from the minimum up to the maximum, as plain values.
  uint64_t now = 2;
  for (uint64_t wait_us : {100 * kMs, 200 * kMs, 350 * kMs, 350 * kMs}) {
    EXPECT_EQ(c.next_deadline_us(), now + wait_us);
    c.tick(now + wait_us - 1);
    EXPECT_EQ(c.state(), LinkState::Waiting);
    now += wait_us;
    c.tick(now);
    EXPECT_EQ(c.state(), LinkState::Connecting);
    ASSERT_TRUE(is(c.next_action(), ActionKind::Resolve));
    c.resolved(now, {"127.0.0.1:6665"});
    actions(c);
    c.attempt_failed(now, 0, "Connection refused");
    EXPECT_EQ(c.next_event().text, "cannot connect to localhost:6665: Connection refused");
  }
}

TEST(Connection, AConnectionThatCameUpStartsAgainFromTheShortestWait) {
  ConnectionOptions o = options();
  o.backoff_min_us = 100 * kMs;
  Connection c(o);
  c.start(0);
  actions(c);
  c.resolve_failed(0, "cannot resolve host 'x': Name or service not known");
  EXPECT_EQ(c.next_event().text, "cannot resolve host 'x': Name or service not known");
  c.tick(100 * kMs);
  actions(c);
  c.resolve_failed(100 * kMs, "again");
  c.next_event();
  EXPECT_EQ(c.next_deadline_us(), 300 * kMs) << "backed off to 200 ms";
  c.tick(300 * kMs);
  actions(c);
  c.resolved(300 * kMs, {"127.0.0.1:6665"});
  actions(c);
  c.attempt_connected(300 * kMs, 0);
  feed(c, 300 * kMs, node_hello());
  ASSERT_EQ(c.next_event().kind, EventKind::Up);
  c.transport_closed(400 * kMs, "");
  EXPECT_EQ(c.next_event().text, "the node closed the connection");
  EXPECT_EQ(c.next_deadline_us(), 500 * kMs);
}

TEST(Connection, WithoutReconnectAFailureEndsIdle) {
  ConnectionOptions o = options();
  o.reconnect = false;
  Connection c(o);
  c.start(0);
  actions(c);
  c.resolved(0, {"127.0.0.1:6665"});
  actions(c);
  c.attempt_failed(0, 0, "Connection refused");
  EXPECT_EQ(c.next_event().kind, EventKind::Down);
  EXPECT_EQ(c.state(), LinkState::Idle);
  EXPECT_EQ(c.next_deadline_us(), kNoDeadline);
}

TEST(Connection, NoAnswerAtAllTimesOut) {
  Connection c(options());
  c.start(0);
  actions(c);
  c.resolved(0, {"192.0.2.1:6665"});
  actions(c);
  c.tick(10'000 * kMs);
  std::vector<Action> a = actions(c);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_TRUE(is(a[0], ActionKind::Abandon, 0));
  EXPECT_EQ(c.next_event().text, "no connection with localhost:6665 within 10000 ms");
}

TEST(Connection, APeerThatNeverSaysHelloTimesOut) {
  Connection c(options());
  connect(c, 0);
  c.tick(10'000 * kMs);
  EXPECT_TRUE(is(c.next_action(), ActionKind::Close));
  EXPECT_EQ(c.next_event().text, "no handshake with localhost:6665 within 10000 ms");
}

TEST(Connection, TheHelloByteByByteThenTheTimeSync) {
  Connection c(options());
  connect(c, 1000);
  std::vector<Bytes> out = sent(c);
  ASSERT_EQ(out.size(), 2u);
  const Message& ts = msg(out[1]);
  EXPECT_EQ(ts.body_as_TimeSync()->client_send_us(), 1000u);

  Bytes hello = node_hello();
  for (size_t i = 0; i + 1 < hello.size(); ++i) {
    feed(c, 1200, Bytes{hello[i]});
    ASSERT_EQ(c.next_event().kind, EventKind::None) << "after byte " << i;
  }
  feed(c, 1200, Bytes{hello.back()});
  Event e = c.next_event();
  ASSERT_EQ(e.kind, EventKind::Up);
  EXPECT_EQ(e.message->body_as_Hello()->name()->str(), "robot7");
  EXPECT_EQ(c.peer_name(), "robot7");
  EXPECT_EQ(c.connections(), 1u);
  EXPECT_FALSE(c.clock_synced());

  // The node's clock runs 5 s ahead: it received at our 1500 and sent at 1600.
  Bytes reply = time_sync_reply(ts.header()->seq(), 1000, 5'001'500, 5'001'600);
  feed(c, 2100, reply, 3);
  e = c.next_event();
  ASSERT_EQ(e.kind, EventKind::Synced);
  EXPECT_TRUE(c.clock_synced());
  EXPECT_EQ(c.clock_offset_us(), 5'000'000);
}

TEST(Connection, FramesSplitAnywhereComeOutWholeAndInOrder) {
  Bytes stream = join({node_hello(), data(1), data(2), data(3)});
  for (size_t chunk : {size_t(1), size_t(5), size_t(37), stream.size()}) {
    SCOPED_TRACE(chunk);
    Connection c(options());
    connect(c, 0);
    feed(c, 0, stream, chunk);
    EXPECT_EQ(c.next_event().kind, EventKind::Up);
    for (uint32_t seq = 1; seq <= 3; ++seq) {
      Event e = c.next_event();
      ASSERT_EQ(e.kind, EventKind::Frame);
      EXPECT_EQ(e.message->header()->seq(), seq);
      EXPECT_EQ(bytes(e.frame), data(seq));
    }
    EXPECT_EQ(c.next_event().kind, EventKind::None);
  }
}

TEST(Connection, APeerWithAnotherVersionIsDropped) {
  Connection c(options());
  connect(c, 0);
  feed(c, 5, node_hello(2));
  Event e = c.next_event();
  ASSERT_EQ(e.kind, EventKind::Down);
  EXPECT_EQ(e.text, "the node speaks protocol 2, this client 1");
  EXPECT_TRUE(is(c.next_action(), ActionKind::Close));
  EXPECT_EQ(c.state(), LinkState::Waiting);
}

TEST(Connection, APeerThatGoesSilentIsPingedThenDropped) {
  ConnectionOptions o = options();
  o.keepalive_us = 1000 * kMs;
  o.keepalive_timeout_us = 3000 * kMs;
  Connection c(o);
  up(c, 0);
  sent(c);
  EXPECT_EQ(c.next_deadline_us(), 1000 * kMs);
  c.tick(999 * kMs);
  EXPECT_TRUE(c.output().empty());
  c.tick(1000 * kMs);
  std::vector<Bytes> ping = sent(c);
  ASSERT_EQ(ping.size(), 1u);
  EXPECT_EQ(msg(ping[0]).header()->kind(), Kind::TimeSync);

  // Its reply is swallowed; it counts as hearing from the node.
  feed(c, 1200 * kMs, time_sync_reply(msg(ping[0]).header()->seq(), 1000 * kMs, 7, 8));
  EXPECT_EQ(c.next_event().kind, EventKind::None);
  EXPECT_EQ(c.next_deadline_us(), 2200 * kMs);

  // Then silence: a ping at 2.2 s, and at 5.2 s the connection is dropped.
  c.tick(2200 * kMs);
  ASSERT_EQ(sent(c).size(), 1u);
  c.tick(5200 * kMs - 1);
  EXPECT_EQ(c.state(), LinkState::Up);
  c.tick(5200 * kMs);
  EXPECT_TRUE(is(c.next_action(), ActionKind::Close));
  Event e = c.next_event();
  ASSERT_EQ(e.kind, EventKind::Down);
  EXPECT_EQ(e.text, "the node silent for 4000 ms");
}

TEST(Connection, AnOwnerThatDidNotRunForLongIsNotMistakenForSilence) {
  ConnectionOptions o = options();
  o.keepalive_us = 1000 * kMs;
  o.keepalive_timeout_us = 3000 * kMs;
  Connection c(o);
  up(c, 0);
  sent(c);
  c.tick(60'000 * kMs);  // the first look in a minute: a ping, not a verdict
  EXPECT_EQ(c.state(), LinkState::Up);
  EXPECT_EQ(sent(c).size(), 1u);
}

TEST(Connection, BadBytesEndTheConnectionWithTheReason) {
  {
    Connection c(options());
    connect(c, 0);
    Bytes bad = node_hello();
    bad[6] = 0x7F;  // the root offset, far outside the frame
    feed(c, 0, bad);
    Event e = c.next_event();
    ASSERT_EQ(e.kind, EventKind::Down);
    EXPECT_EQ(e.text.rfind("bad frame from the node: ", 0), 0u) << e.text;
  }
  {
    Connection c(options());
    connect(c, 0);
    feed(c, 0, Bytes{0xFF, 0xFF, 0xFF, 0x7F, 1, 2, 3});
    EXPECT_EQ(c.next_event().text, "the node sent a frame over the limit (2147483647 bytes)");
  }
  {
    Connection c(options());
    connect(c, 0);
    feed(c, 0, data(1));
    EXPECT_EQ(c.next_event().text, "the node sent data before its Hello");
  }
}

TEST(Connection, TheNodesErrorIsTheReason) {
  Connection c(options());
  connect(c, 0);
  feed(c, 0, node_error("too many clients (limit 64)"));
  EXPECT_EQ(c.next_event().text, "the node closed the connection: too many clients (limit 64)");
}

TEST(Connection, FramesBeforeTheEndOfTheStreamAreDeliveredFirst) {
  Connection c(options());
  connect(c, 0);
  feed(c, 0, join({node_hello(), data(1), data(2)}));
  c.transport_closed(10, "");
  EXPECT_EQ(c.next_event().kind, EventKind::Up);
  EXPECT_EQ(c.next_event().kind, EventKind::Frame);
  EXPECT_EQ(c.next_event().kind, EventKind::Frame);
  EXPECT_EQ(c.next_event().text, "the node closed the connection");

  Connection cut(options());
  connect(cut, 0);
  Bytes half = node_hello();
  half.resize(half.size() / 2);
  feed(cut, 0, half);
  cut.transport_closed(10, "Connection reset by peer");
  EXPECT_EQ(cut.next_event().text, "connection to localhost:6665 lost: Connection reset by peer inside a frame");
}

TEST(Connection, FramesQueuedWhileConnectingFollowTheHello) {
  Connection c(options());
  EXPECT_FALSE(c.send(data(9))) << "not started";
  c.start(0);
  EXPECT_TRUE(c.send(data(9)));
  EXPECT_TRUE(c.output().empty()) << "nothing to write before a transport is up";
  actions(c);
  c.resolved(0, {"127.0.0.1:6665"});
  actions(c);
  c.attempt_connected(0, 0);
  std::vector<Bytes> out = sent(c);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(msg(out[0]).header()->kind(), Kind::Hello);
  EXPECT_EQ(msg(out[1]).header()->kind(), Kind::TimeSync);
  EXPECT_EQ(out[2], data(9));
}

TEST(Connection, APeerThatDoesNotReadIsDroppedNotQueuedForever) {
  ConnectionOptions o = options();
  o.max_output_bytes = 1000;
  Connection c(o);
  up(c, 0);
  sent(c);
  Bytes frame = data(1);
  size_t fit = 1000 / frame.size();
  for (size_t i = 0; i < fit; ++i) ASSERT_TRUE(c.send(frame));
  EXPECT_FALSE(c.send(frame));
  EXPECT_TRUE(is(c.next_action(), ActionKind::Close));
  EXPECT_EQ(c.next_event().text,
            "the node does not read (" + std::to_string(fit * frame.size()) + " bytes queued)");
}

TEST(Connection, WritesArePartialAsTheSocketTakesThem) {
  Connection c(options());
  connect(c, 0);
  Bytes all = bytes(c.output());
  c.consumed(3);
  EXPECT_EQ(bytes(c.output()), Bytes(all.begin() + 3, all.end()));
  c.consumed(all.size() - 3);
  EXPECT_TRUE(c.output().empty());
}

TEST(Connection, StopEndsQuietly) {
  Connection c(options());
  up(c, 0);
  c.stop();
  EXPECT_TRUE(is(c.next_action(), ActionKind::Close));
  EXPECT_EQ(c.next_event().kind, EventKind::None);
  EXPECT_EQ(c.state(), LinkState::Idle);
  EXPECT_FALSE(c.send(data(1)));
}

// A transport with a handshake of its own (the client says "HI", the peer
// answers "OK") that then flips every byte: enough to show where an
// authenticated, encrypted transport goes, without being one.
class FlipTransport : public Transport {
 public:
  void begin(std::vector<uint8_t>& out) override {
    ready_ = false;
    out.insert(out.end(), {'H', 'I'});
  }
  bool ready() const override { return ready_; }
  bool inbound(std::span<const uint8_t> in, FrameReader& frames, std::vector<uint8_t>&,
               std::string& error) override {
    if (!ready_) {
      if (in.size() < 2 || in[0] != 'O' || in[1] != 'K') {
        error = "no OK";
        return false;
      }
      ready_ = true;
      in = in.subspan(2);
    }
    std::span<uint8_t> space = frames.write_space(in.size());
    for (size_t i = 0; i < in.size(); ++i) space[i] = uint8_t(~in[i]);
    frames.commit(in.size());
    return true;
  }
  void outbound(std::span<const uint8_t> frames, std::vector<uint8_t>& out) override {
    for (uint8_t b : frames) out.push_back(uint8_t(~b));
  }

 private:
  bool ready_ = false;
};

Bytes flipped(const Bytes& in) {
  Bytes out;
  for (uint8_t b : in) out.push_back(uint8_t(~b));
  return out;
}

TEST(Connection, ATransportHandshakeRunsBeforeHelloAndSealsEveryByte) {
  FlipTransport transport;
  Connection c(options(), &transport);
  c.start(0);
  actions(c);
  c.resolved(0, {"127.0.0.1:6665"});
  actions(c);
  EXPECT_TRUE(c.send(data(9)));
  c.attempt_connected(0, 0);
  EXPECT_EQ(bytes(c.output()), (Bytes{'H', 'I'})) << "only the handshake until it completes";
  c.consumed(2);
  feed(c, 1, join({Bytes{'O', 'K'}, flipped(node_hello())}));
  Bytes out = flipped(bytes(c.output()));
  c.consumed(out.size());
  FrameReader reader(1u << 20);
  std::copy(out.begin(), out.end(), reader.write_space(out.size()).begin());
  reader.commit(out.size());
  EXPECT_EQ(msg(bytes(reader.next())).header()->kind(), Kind::Hello);
  EXPECT_EQ(msg(bytes(reader.next())).header()->kind(), Kind::TimeSync);
  EXPECT_EQ(bytes(reader.next()), data(9));
  EXPECT_EQ(c.next_event().kind, EventKind::Up);

  Connection refused(options(), &transport);
  connect(refused, 0);
  feed(refused, 0, Bytes{'N', 'O'});
  EXPECT_EQ(refused.next_event().text, "bad bytes from the node: no OK");
}

TEST(Connection, StateNamesAreTheDocumentedOnes) {
  EXPECT_STREQ(link_state_name(LinkState::Idle), "idle");
  EXPECT_STREQ(link_state_name(LinkState::Waiting), "waiting");
  EXPECT_STREQ(link_state_name(LinkState::Connecting), "connecting");
  EXPECT_STREQ(link_state_name(LinkState::Handshake), "handshake");
  EXPECT_STREQ(link_state_name(LinkState::Up), "up");
}

}  // namespace
}  // namespace troupe::wire
