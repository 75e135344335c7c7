#include "tests/cross/test_client.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

namespace troupe::cross {
namespace {

using Clock = std::chrono::steady_clock;

int remaining_ms(Clock::time_point deadline) {
  auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return left > 0 ? int(left) : 0;
}

}  // namespace

TestClient::~TestClient() {
  if (fd_ >= 0) close(fd_);
}

bool TestClient::connect(uint16_t port, std::string& error) {
  fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (fd_ < 0 || ::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    error = std::string("connect to 127.0.0.1:") + std::to_string(port) + ": " + strerror(errno);
    return false;
  }
  int one = 1;
  setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  const wire::Message* hello = next();
  if (hello == nullptr || hello->header()->kind() != wire::Kind::Hello || hello->body_as_Hello() == nullptr) {
    error = "the node sent no Hello: " + error_;
    return false;
  }
  if (hello->body_as_Hello()->protocol_version() != wire::kProtocolVersion) {
    error = "the node speaks protocol " + std::to_string(hello->body_as_Hello()->protocol_version());
    return false;
  }
  node_name_ = hello->body_as_Hello()->name() ? hello->body_as_Hello()->name()->str() : "";
  auto& b = writer_.start();
  auto body = wire::CreateHello(b, wire::kProtocolVersion, b.CreateString("cross-test"), 1u << 20, 0, 0);
  return send(wire::make_header({}, wire::Kind::Hello, 0, 0, 0), wire::Body::Hello, body.Union());
}

bool TestClient::send_raw(std::span<const uint8_t> bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    ssize_t n = ::send(fd_, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error_ = std::string("send: ") + strerror(errno);
      return false;
    }
    done += size_t(n);
  }
  return true;
}

bool TestClient::send(const wire::Header& header, wire::Body type, flatbuffers::Offset<void> body) {
  return send_raw(writer_.finish(header, type, body));
}

const wire::Message* TestClient::next(int timeout_ms) {
  auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    std::span<const uint8_t> frame = reader_.next();
    if (!frame.empty()) {
      current_.assign(frame.begin(), frame.end());
      wire::VerifyError why{};
      const wire::Message* msg = wire::verify_frame(current_, wire::Limits{}, &why);
      if (msg == nullptr)
        error_ = "a frame from the node failed verification: " + std::string(wire::verify_error_text(why));
      return msg;
    }
    if (reader_.too_large()) {
      error_ = "the node announced a frame over the limit";
      return nullptr;
    }
    pollfd p{fd_, POLLIN, 0};
    int ready = poll(&p, 1, remaining_ms(deadline));
    if (ready == 0) {
      error_ = "no message within " + std::to_string(timeout_ms) + " ms";
      return nullptr;
    }
    if (ready < 0 && errno == EINTR) continue;
    std::span<uint8_t> space = reader_.write_space(16 * 1024);
    ssize_t n = recv(fd_, space.data(), space.size(), 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      closed_ = true;
      error_ = n == 0 ? "the node closed the connection" : std::string("recv: ") + strerror(errno);
      return nullptr;
    }
    reader_.commit(size_t(n));
  }
}

const wire::Message* TestClient::reply(wire::Kind kind, uint32_t seq, int timeout_ms) {
  auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    const wire::Message* msg = next(remaining_ms(deadline));
    if (msg == nullptr) return nullptr;
    const wire::Header& h = *msg->header();
    if (h.kind() == kind && h.seq() == seq) return msg;
    if ((h.kind() == wire::Kind::Ack || h.kind() == wire::Kind::Nack || h.kind() == wire::Kind::Error) &&
        h.seq() == seq) {
      error_ = "got a " + std::string(wire::kind_name(h.kind())) + " instead";
      if (const wire::Error* e = msg->body_as_Error(); e && e->text()) error_ += ": " + e->text()->str();
      return nullptr;
    }
  }
}

const wire::Message* TestClient::data(const wire::Address& addr, int timeout_ms) {
  auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    const wire::Message* msg = next(remaining_ms(deadline));
    if (msg == nullptr) return nullptr;
    if (msg->header()->kind() == wire::Kind::Data && msg->header()->addr() == addr) return msg;
  }
}

bool TestClient::list_devices(std::vector<wire::Address>& out, std::vector<std::string>& drivers) {
  out.clear();
  drivers.clear();
  uint32_t seq = next_seq();
  writer_.start();
  if (!send(wire::make_header({}, wire::Kind::DeviceList, 0, seq, 0))) return false;
  const wire::Message* msg = reply(wire::Kind::DeviceList, seq);
  const wire::DeviceList* list = msg ? msg->body_as_DeviceList() : nullptr;
  if (list == nullptr) return false;
  if (list->devices()) {
    for (const wire::DeviceInfo* d : *list->devices()) {
      out.push_back(d->addr() ? *d->addr() : wire::Address());
      drivers.push_back(d->driver() ? d->driver()->str() : "");
    }
  }
  return true;
}

bool TestClient::open(const wire::Address& addr, wire::Access access, wire::Delivery delivery) {
  uint32_t seq = next_seq();
  auto& b = writer_.start();
  auto body = wire::CreateOpen(b, access, delivery);
  if (!send(wire::make_header(addr, wire::Kind::Open, 0, seq, 0), wire::Body::Open, body.Union()))
    return false;
  return reply(wire::Kind::Ack, seq) != nullptr;
}

bool TestClient::send_vel(const wire::Address& addr, float v, float w) {
  auto& b = writer_.start();
  wire::Pose2d vel(v, 0, w);
  auto body = wire::CreatePosition2dVel(b, &vel);
  return send(
      wire::make_header(addr, wire::Kind::Command, uint8_t(wire::Position2dCmdSub::Vel), next_seq(), 0),
      wire::Body::Position2dVel, body.Union());
}

}  // namespace troupe::cross
