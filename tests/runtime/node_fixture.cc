#include "tests/runtime/node_fixture.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>

#include "runtime/clock.h"

namespace troupe::testing {

Recorder::~Recorder() {
  if (wake_fd_ >= 0) close(wake_fd_);
}

bool Recorder::setup(Node& node, const DriverSetup& setup, std::string& error) {
  if (setup.provides.size() != 1) {
    error = "recorder provides one device";
    return false;
  }
  device_ = setup.provides[0];
  wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  return wake_fd_ >= 0 && node.loop().watch(wake_fd_, EPOLLIN, this);
}

void Recorder::burst(int n) {
  pending_burst_.fetch_add(n);
  uint64_t one = 1;
  (void)!write(wake_fd_, &one, sizeof one);
}

void Recorder::stream(int period_ms) {
  period_ms_.store(period_ms);
  uint64_t one = 1;
  (void)!write(wake_fd_, &one, sizeof one);
}

void Recorder::on_fd(int fd, uint32_t) {
  uint64_t count = 0;
  (void)!read(fd, &count, sizeof count);
  for (int n = pending_burst_.exchange(0), i = 0; i < n; ++i) publish_scan(1.0f + float(i % 7));
  int period = period_ms_.load();
  if (period != running_period_ms_) {
    if (stream_ != 0) node_->loop().cancel_timer(stream_);
    stream_ = period > 0 ? node_->loop().start_timer(0, uint64_t(period) * 1000, this) : 0;
    running_period_ms_ = period;
  }
}

void Recorder::on_command(DeviceId, const wire::Message& cmd) {
  commands.fetch_add(1);
  if (const wire::Position2dVel* v = cmd.body_as_Position2dVel(); v && v->vel()) last_vx.store(v->vel()->x());
}

void Recorder::on_request(DeviceId, const wire::Message& req, RequestToken token) {
  requests.fetch_add(1);
  uint8_t sub = req.header()->subtype();
  if (sub == kNeverReply) return;
  if (sub == kReplyLate) {
    late_token_ = token;
    late_ = node_->loop().start_timer(3ull * node_->options().request_timeout_ms * 1000, 0, this);
    return;
  }
  node_->ack(token);
}

void Recorder::on_timer(TimerId id) {
  if (id == late_) {
    node_->ack(late_token_);  // too late: the node has answered Timeout already
    late_ = 0;
    return;
  }
  publish_scan(2.5f);
}

void Recorder::publish_scan(float range_m) {
  auto& b = node_->begin();
  // Written in place in the builder: a driver need not allocate per sample.
  uint16_t* ranges = nullptr;
  auto vec = b.CreateUninitializedVector<uint16_t>(181, &ranges);
  std::fill(ranges, ranges + 181, uint16_t(range_m * 1000));
  auto body = wire::CreateRangerScan(b, vec, 0.001f, -1.5708f, 0.017453f, 8.0f);
  // Counted before the send: a client may see the scan before this thread
  // runs its next line.
  published.fetch_add(1);
  node_->publish(device_, uint8_t(wire::RangerDataSub::Scan), wire::Body::RangerScan, body.Union());
}

Node::Options test_options() {
  Node::Options o;
  o.name = "test-node";
  o.listen = "127.0.0.1";
  o.port = 0;
  o.request_timeout_ms = 300;
  return o;
}

RecorderNode::RecorderNode(wire::Interface iface, Node::Options options, client::Client::Options client_options)
    : node(std::move(options)), recorder(new Recorder) {
  node.add_device(iface, 0, recorder);
  node.start();
  client = std::make_unique<client::Client>("127.0.0.1", node.port(), std::move(client_options));
  EXPECT_TRUE(client->connect()) << client->error();
}

NodeThread::NodeThread(Node::Options options) : node_(std::move(options)) {}

NodeThread::~NodeThread() { stop(); }

DeviceId NodeThread::add_device(wire::Interface iface, uint16_t index, Driver* driver, const char* name,
                                uint16_t robot) {
  DeviceId id = node_.add_device(addr(iface, index, robot), driver, name);
  EXPECT_NE(id, kNoDevice);
  for (auto& [d, devices] : pending_) {
    if (d == driver) {
      devices.push_back(id);
      return id;
    }
  }
  pending_.push_back({driver, {id}});
  return id;
}

void NodeThread::start() {
  for (auto& [driver, devices] : pending_) {
    DriverSetup setup;
    setup.name = "test";
    setup.provides = devices;
    std::string error;
    ASSERT_TRUE(node_.add_driver(std::unique_ptr<Driver>(driver), setup, error)) << error;
  }
  pending_.clear();
  std::string error;
  ASSERT_TRUE(node_.start(error)) << error;
  port_ = node_.port();
  thread_ = std::thread([this] {
    while (!stop_.load()) node_.poll(5000);
  });
}

void NodeThread::stop() {
  if (!thread_.joinable()) return;
  stop_.store(true);
  thread_.join();
  node_.shutdown();
}

RawConnection::RawConnection(uint16_t port, int rcvbuf_bytes) {
  fd_ = socket(AF_INET, SOCK_STREAM, 0);
  if (rcvbuf_bytes > 0) setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &rcvbuf_bytes, sizeof rcvbuf_bytes);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    close(fd_);
    fd_ = -1;
  }
}

RawConnection::~RawConnection() {
  if (fd_ >= 0) close(fd_);
}

bool RawConnection::send_bytes(std::span<const uint8_t> bytes) {
  return send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL) == ssize_t(bytes.size());
}

void RawConnection::shutdown_write() { shutdown(fd_, SHUT_WR); }

std::vector<uint8_t> RawConnection::read_frame(int timeout_ms) {
  uint64_t deadline = monotonic_us() + uint64_t(timeout_ms) * 1000;
  for (;;) {
    auto frame = reader_.next();
    if (!frame.empty()) return {frame.begin(), frame.end()};
    if (eof_) return {};
    uint64_t now = monotonic_us();
    if (now >= deadline) return {};
    pollfd p{fd_, POLLIN, 0};
    if (poll(&p, 1, int((deadline - now) / 1000) + 1) <= 0) continue;
    auto space = reader_.write_space(65536);
    ssize_t n = recv(fd_, space.data(), space.size(), 0);
    if (n <= 0) {
      eof_ = true;
      continue;
    }
    total_ += size_t(n);
    reader_.commit(size_t(n));
  }
}

std::vector<uint8_t> RawConnection::read_until(wire::Kind kind, int timeout_ms) {
  uint64_t deadline = monotonic_us() + uint64_t(timeout_ms) * 1000;
  for (uint64_t now = monotonic_us(); now < deadline; now = monotonic_us()) {
    auto f = read_frame(int((deadline - now) / 1000) + 1);
    if (f.empty()) return {};
    const wire::Message* m = wire::verify_frame(f, wire::Limits{});
    if (m != nullptr && m->header()->kind() == kind) return f;
  }
  return {};
}

bool RawConnection::wait_closed(int timeout_ms) {
  uint64_t deadline = monotonic_us() + uint64_t(timeout_ms) * 1000;
  while (!eof_ && monotonic_us() < deadline) read_frame(int((deadline - monotonic_us()) / 1000) + 1);
  return eof_;
}

std::vector<uint8_t> empty_frame(const wire::Address& addr, wire::Kind kind, uint8_t subtype, uint32_t seq) {
  wire::MessageWriter w;
  auto f = w.empty(wire::make_header(addr, kind, subtype, seq, monotonic_us()));
  return {f.begin(), f.end()};
}

std::vector<uint8_t> vel_frame(const wire::Address& addr, float vx, uint32_t seq) {
  wire::MessageWriter w;
  auto& b = w.start();
  wire::Pose2d vel(vx, 0, 0);
  auto body = wire::CreatePosition2dVel(b, &vel);
  auto f = w.finish(wire::make_header(addr, wire::Kind::Command, 1, seq, monotonic_us()), wire::Body::Position2dVel,
                    body.Union());
  return {f.begin(), f.end()};
}

}  // namespace troupe::testing
