#include "wire/connection/socket_link.h"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "wire/clock.h"

namespace troupe::wire {
namespace {

// Reads per readiness event: enough to drain a burst, bounded so that one
// busy connection cannot keep a shared poll loop to itself.
constexpr int kReadRounds = 16;
constexpr size_t kReadChunk = 16 * 1024;

}  // namespace

SocketLink::SocketLink(std::string host, uint16_t port, ConnectionOptions options, Resolver resolver,
                       Transport* transport)
    : host_(std::move(host)), port_(port), resolver_(std::move(resolver)), conn_(std::move(options), transport) {}

SocketLink::~SocketLink() {
  stop();
}

void SocketLink::start() {
  conn_.start(monotonic_us());
  perform();
}

void SocketLink::stop() {
  conn_.stop();
  while (conn_.next_action().kind != ActionKind::None) {
  }
  for (const Attempt& a : attempts_) release(a.fd);
  attempts_.clear();
  close_fd();
}

bool SocketLink::open_transport(int timeout_ms, std::string& error) {
  start();
  uint64_t deadline = monotonic_us() + uint64_t(timeout_ms) * 1000u;
  while (conn_.state() == LinkState::Connecting) {
    uint64_t now = monotonic_us();
    if (now >= deadline) break;
    wait(int((deadline - now + 999) / 1000));
  }
  if (conn_.state() == LinkState::Handshake || conn_.state() == LinkState::Up) return true;
  error = conn_.error().empty() ? "no connection to " + conn_.options().target : conn_.error();
  return false;
}

void SocketLink::release(int fd) {
  if (close_hook_) close_hook_(fd);
  ::close(fd);
}

void SocketLink::close_fd() {
  if (fd_ >= 0) release(fd_);
  fd_ = -1;
}

void SocketLink::perform() {
  for (Action a = conn_.next_action(); a.kind != ActionKind::None; a = conn_.next_action()) {
    switch (a.kind) {
      case ActionKind::Resolve: {
        std::string error;
        if (!resolver_(host_, port_, endpoints_, error)) {
          conn_.resolve_failed(monotonic_us(), error);
          break;
        }
        std::vector<std::string> names;
        for (const Endpoint& e : endpoints_) names.push_back(e.text());
        conn_.resolved(monotonic_us(), std::move(names));
        break;
      }
      case ActionKind::Connect:
        connect_candidate(a.candidate);
        break;
      case ActionKind::Abandon:
        close_attempt(a.candidate);
        break;
      case ActionKind::Close:
        close_fd();
        break;
      case ActionKind::None:
        break;
    }
  }
  flush();
}

void SocketLink::connect_candidate(uint32_t candidate) {
  const Endpoint& e = endpoints_.at(candidate);
  int fd = socket(e.addr.ss_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) {
    conn_.attempt_failed(monotonic_us(), candidate, strerror(errno));
    return;
  }
  int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  attempts_.push_back({candidate, fd});
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&e.addr), e.len) == 0) {
    attempt_done(attempts_.size() - 1, 0);
  } else if (errno != EINPROGRESS) {
    attempt_done(attempts_.size() - 1, errno);
  }
}

void SocketLink::attempt_done(size_t index, int error) {
  Attempt a = attempts_[index];
  attempts_.erase(attempts_.begin() + long(index));
  if (error != 0) {
    release(a.fd);
    conn_.attempt_failed(monotonic_us(), a.candidate, strerror(error));
    return;
  }
  close_fd();
  fd_ = a.fd;
  conn_.attempt_connected(monotonic_us(), a.candidate);
}

void SocketLink::close_attempt(uint32_t candidate) {
  for (size_t i = 0; i < attempts_.size(); ++i) {
    if (attempts_[i].candidate != candidate) continue;
    release(attempts_[i].fd);
    attempts_.erase(attempts_.begin() + long(i));
    return;
  }
}

int SocketLink::poll_fds(pollfd* fds, int max) const {
  int n = 0;
  if (fd_ >= 0 && n < max) fds[n++] = pollfd{fd_, short(POLLIN | (conn_.output().empty() ? 0 : POLLOUT)), 0};
  for (const Attempt& a : attempts_) {
    if (n < max) fds[n++] = pollfd{a.fd, POLLOUT, 0};
  }
  return n;
}

void SocketLink::process(const pollfd* fds, int n) {
  for (int i = 0; i < n; ++i) {
    if (fds[i].revents == 0 || fds[i].fd < 0) continue;
    if (fds[i].fd == fd_) {
      if (fds[i].revents & POLLOUT) flush();
      if (fd_ >= 0 && (fds[i].revents & (POLLIN | POLLHUP | POLLERR))) read();
      continue;
    }
    for (size_t k = 0; k < attempts_.size(); ++k) {
      if (attempts_[k].fd != fds[i].fd) continue;
      int err = 0;
      socklen_t len = sizeof err;
      if (getsockopt(attempts_[k].fd, SOL_SOCKET, SO_ERROR, &err, &len) != 0) err = errno;
      attempt_done(k, err);
      perform();
      break;
    }
  }
  conn_.tick(monotonic_us());
  perform();
}

int SocketLink::next_timeout_ms() const {
  uint64_t at = conn_.next_deadline_us();
  if (at == kNoDeadline) return -1;
  uint64_t now = monotonic_us();
  return at > now ? int(std::min<uint64_t>((at - now + 999) / 1000, 1u << 30)) : 0;
}

void SocketLink::wait(int timeout_ms) {
  pollfd fds[1 + kMaxAttemptsInFlight];
  int n = poll_fds(fds, int(std::size(fds)));
  int wait = timeout_ms;
  int timer = next_timeout_ms();
  if (timer >= 0 && (wait < 0 || timer < wait)) wait = timer;
  if (poll(fds, nfds_t(n), wait) < 0 && errno != EINTR) return;
  process(fds, n);
}

Event SocketLink::next_event() {
  Event e = conn_.next_event();
  perform();
  return e;
}

bool SocketLink::send(std::span<const uint8_t> frame) {
  bool queued = conn_.send(frame);
  perform();
  return queued;
}

uint32_t SocketLink::request_time_sync() {
  uint32_t seq = conn_.request_time_sync(monotonic_us());
  perform();
  return seq;
}

void SocketLink::close(std::string why) {
  conn_.close(monotonic_us(), std::move(why));
  perform();
}

void SocketLink::flush() {
  while (fd_ >= 0) {
    std::span<const uint8_t> out = conn_.output();
    if (out.empty()) return;
    ssize_t n = ::send(fd_, out.data(), out.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n > 0) {
      conn_.consumed(size_t(n));
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;
    int err = errno;
    close_fd();
    conn_.transport_closed(monotonic_us(), strerror(err));
  }
}

void SocketLink::read() {
  for (int round = 0; round < kReadRounds && fd_ >= 0; ++round) {
    std::span<uint8_t> space = conn_.read_space(kReadChunk);
    ssize_t n = recv(fd_, space.data(), space.size(), MSG_DONTWAIT);
    if (n > 0) {
      conn_.received(monotonic_us(), size_t(n));
      if (size_t(n) < space.size()) return;  // drained
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;
    int err = n == 0 ? 0 : errno;
    close_fd();
    conn_.transport_closed(monotonic_us(), err == 0 ? "" : strerror(err));
  }
}

}  // namespace troupe::wire
