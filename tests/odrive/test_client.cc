#include "tests/odrive/test_client.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace troupe::testing {

TestClient::~TestClient() {
  if (fd_ >= 0) close(fd_);
}

bool TestClient::connect(uint16_t port, std::string& error) {
  fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  // The listening socket's backlog completes the handshake without the
  // node's loop running, so a blocking connect returns at once.
  if (fd_ < 0 || ::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    error = std::string("connect to 127.0.0.1:") + std::to_string(port) + ": " + strerror(errno);
    return false;
  }
  int one = 1;
  setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  return true;
}

void TestClient::send(std::span<const uint8_t> frame) {
  // Test frames are small: the socket buffer always takes them whole.
  if (fd_ >= 0 && ::send(fd_, frame.data(), frame.size(), MSG_NOSIGNAL) != ssize_t(frame.size())) {
    close(fd_);
    fd_ = -1;
  }
}

void TestClient::open(const wire::Address& addr) {
  auto& b = writer_.start();
  auto body = wire::CreateOpen(b, wire::Access::All, wire::Delivery::Push);
  send(writer_.finish(wire::make_header(addr, wire::Kind::Open, 0, ++seq_, 0), wire::Body::Open,
                      body.Union()));
}

void TestClient::command_vel(const wire::Address& addr, float v, float w) {
  auto& b = writer_.start();
  wire::Pose2d vel(v, 0, w);
  auto body = wire::CreatePosition2dVel(b, &vel);
  send(writer_.finish(
      wire::make_header(addr, wire::Kind::Command, uint8_t(wire::Position2dCmdSub::Vel), ++seq_, 0),
      wire::Body::Position2dVel, body.Union()));
}

uint32_t TestClient::request(const wire::Address& addr, wire::Position2dReqSub sub, wire::Body type,
                             flatbuffers::Offset<void> body) {
  uint32_t seq = ++seq_;
  send(writer_.finish(wire::make_header(addr, wire::Kind::Request, uint8_t(sub), seq, 0), type, body));
  return seq;
}

uint32_t TestClient::request_motor_power(const wire::Address& addr, bool on) {
  auto& b = writer_.start();
  auto body = wire::CreateSwitch(b, on);
  return request(addr, wire::Position2dReqSub::MotorPower, wire::Body::Switch, body.Union());
}

uint32_t TestClient::request_reset_odometry(const wire::Address& addr) {
  writer_.start();
  return request(addr, wire::Position2dReqSub::ResetOdometry, wire::Body::NONE, 0);
}

uint32_t TestClient::request_set_odometry(const wire::Address& addr, float x, float y, float a) {
  auto& b = writer_.start();
  wire::Pose2d pose(x, y, a);
  auto body = wire::CreatePosition2dSetOdom(b, &pose);
  return request(addr, wire::Position2dReqSub::SetOdometry, wire::Body::Position2dSetOdom, body.Union());
}

uint32_t TestClient::request_geometry(const wire::Address& addr) {
  writer_.start();
  return request(addr, wire::Position2dReqSub::Geometry, wire::Body::NONE, 0);
}

Reply TestClient::reply(uint32_t seq) const {
  auto it = replies_.find(seq);
  return it == replies_.end() ? Reply{} : it->second;
}

bool TestClient::pump() {
  while (fd_ >= 0) {
    std::span<uint8_t> space = reader_.write_space(4096);
    ssize_t n = recv(fd_, space.data(), space.size(), MSG_DONTWAIT);
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    if (n <= 0) {
      close(fd_);
      fd_ = -1;
      return false;
    }
    reader_.commit(size_t(n));
    for (auto frame = reader_.next(); !frame.empty(); frame = reader_.next()) {
      const wire::Message* msg = wire::verify_frame(frame, wire::Limits{});
      if (msg != nullptr) handle(*msg);
    }
  }
  return fd_ >= 0;
}

void TestClient::handle(const wire::Message& msg) {
  const wire::Header& h = *msg.header();
  switch (h.kind()) {
    case wire::Kind::Data:
      if (const auto* s = msg.body_as_Position2dState()) {
        PositionSample& p = positions_[wire::address_key(h.addr())];
        p.count++;
        p.seq = h.seq();
        if (s->pose()) p.x = s->pose()->x(), p.y = s->pose()->y(), p.a = s->pose()->a();
        if (s->vel()) p.vx = s->vel()->x(), p.va = s->vel()->a();
        p.stall = s->stall();
        p.fault = s->fault() ? s->fault()->str() : std::string();
      } else if (const auto* pw = msg.body_as_PowerState()) {
        PowerSample& p = powers_[wire::address_key(h.addr())];
        p.count++;
        p.volts = pw->volts().value_or(0);
      }
      break;
    case wire::Kind::Ack:
    case wire::Kind::Nack: {
      Reply& r = replies_[h.seq()];
      r.kind = h.kind();
      if (const auto* e = msg.body_as_Error(); e && e->text()) r.text = e->text()->str();
      if (const auto* g = msg.body_as_Position2dGeometry(); g && g->size()) {
        geometry_length = g->size()->x();
        geometry_width = g->size()->y();
      }
      break;
    }
    default:
      break;
  }
}

}  // namespace troupe::testing
