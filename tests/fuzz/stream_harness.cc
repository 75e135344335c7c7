#include "tests/fuzz/stream_harness.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "runtime/log.h"
#include "wire/frame.h"
#include "wire/writer.h"

namespace troupe::fuzz {
namespace {

// Bounds on how long the node may take, in loop iterations of at most 1 ms:
// far above what a served client needs, so only a node that stopped serving
// hits them.
constexpr int kMaxPumps = 5000;

[[noreturn]] void fail(const char* why) {
  fprintf(stderr, "fuzz harness: %s\n", why);
  __builtin_trap();
}

int connect_loopback(uint16_t port) {
  int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  // On loopback the kernel completes the connect from the listen backlog:
  // it returns before the node, in this same thread, has accepted.
  if (fd < 0 || connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) fail("cannot connect to the node");
  int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  return fd;
}

// Reads what is there; false once the peer has closed.
bool drain(int fd, wire::FrameReader* reader) {
  for (;;) {
    uint8_t scratch[4096];
    std::span<uint8_t> space = reader ? reader->write_space(4096) : std::span<uint8_t>(scratch);
    ssize_t n = recv(fd, space.data(), space.size(), MSG_DONTWAIT);
    if (n > 0) {
      if (reader) reader->commit(size_t(n));
      continue;
    }
    return n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR);
  }
}

bool send_all(int fd, std::span<const uint8_t> bytes) {
  return send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL) == ssize_t(bytes.size());
}

}  // namespace

Node::Options fuzz_node_options() {
  Node::Options o;
  o.name = "fuzz";
  o.listen = "127.0.0.1";
  o.port = 0;
  o.udp = false;
  return o;
}

StreamHarness::StreamHarness(Node& node, std::function<void()> tick) : node_(node), tick_(std::move(tick)) {
  set_log_level(LogLevel::Error);  // a log line per refused frame would slow the fuzzer tenfold
  good_ = connect_loopback(node_.port());
  wire::MessageWriter w;
  auto& b = w.start();
  auto hello = wire::CreateHello(b, wire::kProtocolVersion, b.CreateString("well-behaved"), 1u << 20);
  if (!send_all(good_, w.finish(wire::make_header({}, wire::Kind::Hello, 0, 0, 0), wire::Body::Hello, hello.Union()))) {
    fail("the well-behaved client cannot send its Hello");
  }
  check_served();
}

void StreamHarness::pump(int64_t wait_us) {
  node_.poll(wait_us);
  if (tick_) tick_();
}

void StreamHarness::run(const uint8_t* data, size_t size) {
  if (size == 0) return;
  const size_t chunk = 1 + data[0] % 64;  // how the stream is cut into writes
  ++data;
  --size;
  const int fd = connect_loopback(node_.port());
  for (size_t pos = 0; pos < size;) {
    const size_t n = std::min(chunk, size - pos);
    // A node that closed this connection makes the send fail: the rest of
    // the input then has nowhere to go.
    if (send(fd, data + pos, n, MSG_NOSIGNAL | MSG_DONTWAIT) != ssize_t(n)) break;
    pos += n;
    pump(0);
    drain(fd, nullptr);
  }
  // End of stream; the node answers a frame cut short with an Error, and
  // closes in any case.
  shutdown(fd, SHUT_WR);
  for (int i = 0; i < kMaxPumps && drain(fd, nullptr); ++i) pump(1000);
  close(fd);
  pump(0);
  check_served();
}

void StreamHarness::check_served() {
  const uint32_t pull_seq = ++seq_, list_seq = ++seq_;
  wire::MessageWriter w;
  const wire::Address base(0, uint16_t(wire::Interface::Position2d), 0);
  if (!send_all(good_, w.empty(wire::make_header(base, wire::Kind::Pull, 0, pull_seq, 0))) ||
      !send_all(good_, w.empty(wire::make_header({}, wire::Kind::DeviceList, 0, list_seq, 0)))) {
    fail("the well-behaved client's connection is gone");
  }
  wire::FrameReader reader(1u << 24);
  bool pulled = false;
  for (int i = 0; i < kMaxPumps; ++i) {
    pump(1000);
    if (!drain(good_, &reader)) fail("the node closed the well-behaved client's connection");
    for (auto frame = reader.next(); !frame.empty(); frame = reader.next()) {
      const wire::Message* m = wire::verify_frame(frame, wire::Limits{});
      if (m == nullptr) fail("the node sent a frame its own verifier refuses");
      const wire::Header& h = *m->header();
      if (h.kind() == wire::Kind::Error) fail("the node sent the well-behaved client an Error");
      if (const wire::Position2dState* s = m->body_as_Position2dState(); s && s->pose() && s->vel()) {
        const wire::Pose2d& p = *s->pose();
        const wire::Pose2d& v = *s->vel();
        if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.a()) || !std::isfinite(v.x()) ||
            !std::isfinite(v.a())) {
          fail("the base's odometry is not finite");
        }
      }
      if (h.kind() == wire::Kind::Ack && h.seq() == pull_seq) pulled = true;
      if (h.kind() == wire::Kind::DeviceList && h.seq() == list_seq) {
        if (!pulled) fail("the Pull was not answered before the device list");
        return;
      }
    }
  }
  fail("the well-behaved client was not answered");
}

}  // namespace troupe::fuzz
