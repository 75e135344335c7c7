#include "wire/record/session.h"

#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "runtime/clock.h"

namespace troupe::record {
namespace {

int remaining_ms(uint64_t deadline_us) {
  uint64_t now = monotonic_us();
  return now >= deadline_us ? 0 : int((deadline_us - now + 999) / 1000);
}

// Connects within the deadline; returns the socket or -1 with `error`.
int connect_tcp(const std::string& host, uint16_t port, uint64_t deadline_us, std::string& error) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_NUMERICSERV;
  addrinfo* found = nullptr;
  std::string port_text = std::to_string(port);
  if (int rc = getaddrinfo(host.c_str(), port_text.c_str(), &hints, &found); rc != 0) {
    error = "cannot resolve host '" + host + "': " + gai_strerror(rc);
    return -1;
  }
  int fd = -1;
  int last_errno = ETIMEDOUT;
  for (addrinfo* ai = found; ai != nullptr && fd < 0; ai = ai->ai_next) {
    int s = socket(ai->ai_family, ai->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, ai->ai_protocol);
    if (s < 0) continue;
    int one = 1;
    setsockopt(s, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    if (::connect(s, ai->ai_addr, ai->ai_addrlen) != 0 && errno != EINPROGRESS) {
      last_errno = errno;
      ::close(s);
      continue;
    }
    pollfd p{s, POLLOUT, 0};
    int err = ETIMEDOUT;
    if (poll(&p, 1, remaining_ms(deadline_us)) == 1) {
      socklen_t len = sizeof err;
      getsockopt(s, SOL_SOCKET, SO_ERROR, &err, &len);
    }
    if (err == 0) {
      fd = s;
    } else {
      last_errno = err;
      ::close(s);
    }
  }
  freeaddrinfo(found);
  if (fd < 0) error = "cannot connect to " + host + ":" + port_text + ": " + strerror(last_errno);
  return fd;
}

}  // namespace

Session::Session(std::string client_name, wire::Limits limits)
    : name_(std::move(client_name)), limits_(limits), reader_(limits.max_frame_bytes) {}

Session::~Session() {
  close();
}

void Session::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

bool Session::connect(const std::string& host, uint16_t port, int timeout_ms, std::string& error) {
  close();
  host_ = host;
  reader_ = wire::FrameReader(limits_.max_frame_bytes);
  node_error_.clear();
  uint64_t deadline = monotonic_us() + uint64_t(timeout_ms) * 1000u;
  fd_ = connect_tcp(host, port, deadline, error);
  if (fd_ < 0) return false;
  auto& b = begin();
  auto hello = wire::CreateHello(b, wire::kProtocolVersion, b.CreateString(name_), limits_.max_frame_bytes, 0,
                                 monotonic_us());
  if (!send({}, wire::Kind::Hello, 0, error, wire::Body::Hello, hello.Union())) return false;
  for (;;) {
    std::span<const uint8_t> frame;
    const wire::Message* msg = nullptr;
    Read r = read(remaining_ms(deadline), frame, msg, error);
    if (r == Read::Timeout) error = "timed out waiting for the Hello of " + host + ":" + std::to_string(port);
    if (r != Read::Frame) {
      close();
      return false;
    }
    const wire::Hello* h = msg->body_as_Hello();
    if (msg->header()->kind() != wire::Kind::Hello || h == nullptr) continue;
    if (h->protocol_version() != wire::kProtocolVersion) {
      error = "node speaks protocol " + std::to_string(h->protocol_version()) + ", this program " +
              std::to_string(wire::kProtocolVersion);
      close();
      return false;
    }
    hello_.assign(frame.begin(), frame.end());
    node_name_ = h->name() ? h->name()->str() : std::string();
    return true;
  }
}

bool Session::send(std::span<const uint8_t> frame, std::string& error) {
  size_t sent = 0;
  while (fd_ >= 0 && sent < frame.size()) {
    ssize_t n = ::send(fd_, frame.data() + sent, frame.size() - sent, MSG_NOSIGNAL);
    if (n > 0) {
      sent += size_t(n);
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      pollfd p{fd_, POLLOUT, 0};
      poll(&p, 1, 1000);
    } else {
      error = "connection to " + host_ + " lost: " + strerror(errno);
      close();
      return false;
    }
  }
  return fd_ >= 0;
}

bool Session::send(const wire::Address& addr, wire::Kind kind, uint32_t seq, std::string& error,
                   wire::Body type, flatbuffers::Offset<void> body) {
  return send(writer_.finish(wire::make_header(addr, kind, 0, seq, monotonic_us()), type, body), error);
}

Session::Read Session::read(int timeout_ms, std::span<const uint8_t>& frame, const wire::Message*& msg,
                            std::string& error) {
  uint64_t deadline = timeout_ms < 0 ? UINT64_MAX : monotonic_us() + uint64_t(timeout_ms) * 1000u;
  for (;;) {
    if (fd_ < 0) {
      error = "not connected";
      return Read::Closed;
    }
    frame = reader_.next();
    if (!frame.empty()) {
      wire::VerifyError why{};
      msg = wire::verify_frame(frame, limits_, &why);
      if (msg == nullptr) {
        error = "bad frame from " + host_ + ": " + std::string(wire::verify_error_text(why));
        close();
        return Read::Closed;
      }
      if (msg->header()->kind() == wire::Kind::Error) {
        const wire::Error* e = msg->body_as_Error();
        node_error_ = e && e->text() ? e->text()->str() : "error";
      }
      return Read::Frame;
    }
    if (reader_.too_large()) {
      error =
          host_ + " sent a frame over the limit (" + std::to_string(reader_.announced_bytes()) + " bytes)";
      close();
      return Read::Closed;
    }
    pollfd p{fd_, POLLIN, 0};
    int wait = timeout_ms < 0 ? -1 : remaining_ms(deadline);
    int rc = poll(&p, 1, wait);
    if (rc < 0 && errno == EINTR) continue;
    if (rc == 0) return Read::Timeout;
    std::span<uint8_t> space = reader_.write_space(16 * 1024);
    ssize_t n = recv(fd_, space.data(), space.size(), MSG_DONTWAIT);
    if (n < 0 && (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK)) continue;
    if (n <= 0) {
      error = n == 0 ? (node_error_.empty() ? "connection closed by " + host_
                                            : host_ + " closed the connection: " + node_error_)
                     : "connection to " + host_ + " lost: " + strerror(errno);
      close();
      return Read::Closed;
    }
    reader_.commit(size_t(n));
  }
}

}  // namespace troupe::record
