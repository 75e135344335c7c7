#include "tests/device_harness/wire_client.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace troupe::testing {

WireClient::~WireClient() {
  if (fd_ >= 0) close(fd_);
}

bool WireClient::connect(uint16_t port, std::string& error) {
  fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  // The kernel completes a loopback connect from the listen backlog, so this
  // returns before the node (in this same thread) has accepted.
  if (fd_ < 0 || ::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    error = std::string("connect: ") + strerror(errno);
    return false;
  }
  int one = 1;
  setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  fcntl(fd_, F_SETFL, fcntl(fd_, F_GETFL, 0) | O_NONBLOCK);
  return true;
}

void WireClient::send(std::span<const uint8_t> frame) {
  size_t done = 0;
  while (done < frame.size()) {
    ssize_t n = ::send(fd_, frame.data() + done, frame.size() - done, MSG_NOSIGNAL);
    if (n > 0) {
      done += size_t(n);
    } else if (n < 0 && errno != EINTR && errno != EAGAIN) {
      closed_ = true;
      return;
    }
  }
}

void WireClient::open(const wire::Address& addr) {
  auto& b = writer_.start();
  auto body = wire::CreateOpen(b, wire::Access::All, wire::Delivery::Push);
  send(writer_.finish(wire::make_header(addr, wire::Kind::Open, 0, ++seq_, 0), wire::Body::Open,
                      body.Union()));
}

void WireClient::send_vel(const wire::Address& addr, float v, float w) {
  auto& b = writer_.start();
  wire::Pose2d vel(v, 0, w);
  auto body = wire::CreatePosition2dVel(b, &vel);
  send(writer_.finish(
      wire::make_header(addr, wire::Kind::Command, uint8_t(wire::Position2dCmdSub::Vel), ++seq_, 0),
      wire::Body::Position2dVel, body.Union()));
}

uint32_t WireClient::request(const wire::Address& addr, uint8_t subtype, wire::Body type,
                             flatbuffers::Offset<void> (*build)(flatbuffers::FlatBufferBuilder&)) {
  auto& b = writer_.start();
  flatbuffers::Offset<void> body = build ? build(b) : 0;
  uint32_t seq = ++seq_;
  send(writer_.finish(wire::make_header(addr, wire::Kind::Request, subtype, seq, 0), type, body));
  return seq;
}

uint32_t WireClient::request_switch(const wire::Address& addr, uint8_t subtype, bool on) {
  auto& b = writer_.start();
  auto body = wire::CreateSwitch(b, on);
  uint32_t seq = ++seq_;
  send(writer_.finish(wire::make_header(addr, wire::Kind::Request, subtype, seq, 0), wire::Body::Switch,
                      body.Union()));
  return seq;
}

void WireClient::poll() {
  if (fd_ < 0 || closed_) return;
  for (;;) {
    std::span<uint8_t> space = reader_.write_space(16 * 1024);
    ssize_t n = recv(fd_, space.data(), space.size(), MSG_DONTWAIT);
    if (n == 0) closed_ = true;
    if (n <= 0) break;
    reader_.commit(size_t(n));
  }
  wire::Limits limits;
  for (std::span<const uint8_t> frame; !(frame = reader_.next()).empty();) {
    const wire::Message* msg = wire::verify_frame(frame, limits);
    if (msg == nullptr) continue;
    const wire::Header& h = *msg->header();
    if (h.kind() == wire::Kind::Data) {
      Log& log = data_[wire::address_key(h.addr())];
      ++log.count;
      log.last.assign(frame.begin(), frame.end());
    } else if (h.kind() == wire::Kind::Ack || h.kind() == wire::Kind::Nack) {
      replies_[h.seq()].assign(frame.begin(), frame.end());
    }
  }
}

uint32_t WireClient::count(const wire::Address& addr) const {
  auto it = data_.find(wire::address_key(addr));
  return it == data_.end() ? 0 : it->second.count;
}

const wire::Message* WireClient::last(const wire::Address& addr) const {
  auto it = data_.find(wire::address_key(addr));
  return it == data_.end() ? nullptr : wire::trusted_message(it->second.last);
}

const wire::Message* WireClient::reply(uint32_t seq) const {
  auto it = replies_.find(seq);
  return it == replies_.end() ? nullptr : wire::trusted_message(it->second);
}

}  // namespace troupe::testing
