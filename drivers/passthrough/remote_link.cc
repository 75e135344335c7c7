#include "drivers/passthrough/remote_link.h"

#include <arpa/inet.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace troupe::drivers::passthrough {

const char* link_state_name(LinkState s) {
  switch (s) {
    case LinkState::Waiting:
      return "waiting";
    case LinkState::Connecting:
      return "connecting";
    case LinkState::Handshake:
      return "handshake";
    case LinkState::Up:
      return "up";
  }
  return "?";
}

RemoteLink::RemoteLink(EventLoop& loop, LinkListener& listener)
    : loop_(loop), listener_(listener), reader_(wire::Limits{}.max_frame_bytes) {}

RemoteLink::~RemoteLink() {
  stop();
}

bool RemoteLink::start(const LinkOptions& options, std::string& error) {
  options_ = options;
  std::string host = options.host == "localhost" ? "127.0.0.1" : options.host;
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  addr_ = {};
  auto* v4 = reinterpret_cast<sockaddr_in*>(&addr_);
  auto* v6 = reinterpret_cast<sockaddr_in6*>(&addr_);
  if (inet_pton(AF_INET, host.c_str(), &v4->sin_addr) == 1) {
    v4->sin_family = AF_INET;
    v4->sin_port = htons(options.port);
    addr_len_ = sizeof(sockaddr_in);
    remote_text_ = host + ":" + std::to_string(options.port);
  } else if (inet_pton(AF_INET6, host.c_str(), &v6->sin6_addr) == 1) {
    v6->sin6_family = AF_INET6;
    v6->sin6_port = htons(options.port);
    addr_len_ = sizeof(sockaddr_in6);
    remote_text_ = "[" + host + "]:" + std::to_string(options.port);
  } else {
    error =
        "host '" + options.host +
        "' is not a numeric address (a name needs DNS, which would block the node's loop; resolve it first)";
    return false;
  }
  if (options.port == 0) {
    error = "port 0 is not a remote node's port";
    return false;
  }
  reader_ = wire::FrameReader(options_.limits.max_frame_bytes);
  running_ = true;
  since_us_ = loop_.now_us();
  attempt();
  return true;
}

void RemoteLink::stop() {
  running_ = false;
  disarm(step_timer_);
  disarm(ping_timer_);
  if (fd_ >= 0) {
    loop_.unwatch(fd_);
    ::close(fd_);
    fd_ = -1;
  }
  state_ = LinkState::Waiting;
}

void RemoteLink::arm(TimerId& timer, uint64_t delay_us, uint64_t period_us) {
  disarm(timer);
  timer = loop_.start_timer(delay_us, period_us, this);
}

void RemoteLink::disarm(TimerId& timer) {
  if (timer != 0) loop_.cancel_timer(timer);
  timer = 0;
}

void RemoteLink::set_state(LinkState s) {
  if (s == state_) return;
  state_ = s;
  since_us_ = loop_.now_us();
}

void RemoteLink::attempt() {
  int fd = socket(addr_.ss_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) return close(std::string("socket: ") + strerror(errno));
  int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  fd_ = fd;
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr_), addr_len_) != 0 && errno != EINPROGRESS) {
    return close("cannot connect to " + remote_text_ + ": " + strerror(errno));
  }
  events_ = EPOLLIN | EPOLLOUT;
  if (!loop_.watch(fd, events_, this)) return close("cannot watch the socket");
  set_state(LinkState::Connecting);
  arm(step_timer_, options_.connect_timeout_us);
}

void RemoteLink::on_connected() {
  int err = 0;
  socklen_t len = sizeof err;
  getsockopt(fd_, SOL_SOCKET, SO_ERROR, &err, &len);
  if (err != 0) return close("cannot connect to " + remote_text_ + ": " + strerror(err));
  set_state(LinkState::Handshake);
  auto& b = writer_.start();
  auto hello = wire::CreateHello(b, wire::kProtocolVersion, b.CreateString(options_.client_name),
                                 options_.limits.max_frame_bytes, 0, loop_.now_us());
  std::span<const uint8_t> frame = writer_.finish(
      wire::make_header({}, wire::Kind::Hello, 0, 0, loop_.now_us()), wire::Body::Hello, hello.Union());
  out_.insert(out_.end(), frame.begin(), frame.end());
  flush();
}

void RemoteLink::on_fd(int fd, uint32_t events) {
  if (fd != fd_) return;
  if (state_ == LinkState::Connecting) {
    if ((events & (EPOLLOUT | EPOLLERR | EPOLLHUP)) == 0) return;
    on_connected();
    if (fd_ < 0) return;
  }
  if (events & EPOLLOUT) flush();
  if (fd_ >= 0 && (events & (EPOLLIN | EPOLLHUP | EPOLLERR))) read_some();
}

void RemoteLink::on_timer(TimerId id) {
  if (id == step_timer_) {
    step_timer_ = 0;
    if (state_ == LinkState::Waiting) {
      if (running_) attempt();
    } else if (state_ != LinkState::Up) {
      close(std::string("no ") + (state_ == LinkState::Connecting ? "connection" : "handshake") + " with " +
            remote_text_ + " within " + std::to_string(options_.connect_timeout_us / 1000) + " ms");
    }
  } else if (id == ping_timer_) {
    uint64_t now = loop_.now_us();
    if (now - last_rx_us_ > options_.idle_timeout_us) {
      return close("remote " + remote_text_ + " silent for " + std::to_string((now - last_rx_us_) / 1000) +
                   " ms");
    }
    // A TimeSync is the cheapest message every node answers: its reply
    // proves the remote alive when no data flows.
    auto& b = writer_.start();
    auto sync = wire::CreateTimeSync(b, now, 0, 0);
    send(writer_.finish(wire::make_header({}, wire::Kind::TimeSync, 0, next_seq(), now), wire::Body::TimeSync,
                        sync.Union()));
  }
}

void RemoteLink::close(const std::string& why) {
  if (fd_ >= 0) {
    loop_.unwatch(fd_);
    ::close(fd_);
    fd_ = -1;
  }
  disarm(ping_timer_);
  disarm(step_timer_);
  out_.clear();
  out_head_ = 0;
  reader_ = wire::FrameReader(options_.limits.max_frame_bytes);
  last_error_ = why;
  // A link that got as far as Up starts again from the shortest wait; one
  // that keeps failing backs off.
  backoff_us_ =
      backoff_us_ == 0 ? options_.backoff_min_us : std::min(backoff_us_ * 2, options_.backoff_max_us);
  set_state(LinkState::Waiting);
  if (running_) arm(step_timer_, backoff_us_);
  listener_.on_link_down(why);
}

bool RemoteLink::send(std::span<const uint8_t> frame) {
  if (state_ != LinkState::Up) return false;
  if (out_.size() - out_head_ + frame.size() > options_.max_queue_bytes) {
    close("remote " + remote_text_ + " does not read (" + std::to_string(out_.size() - out_head_) +
          " bytes queued)");
    return false;
  }
  if (out_head_ > 0 && out_head_ >= out_.size() / 2) {
    out_.erase(out_.begin(), out_.begin() + long(out_head_));
    out_head_ = 0;
  }
  out_.insert(out_.end(), frame.begin(), frame.end());
  flush();
  return fd_ >= 0;
}

void RemoteLink::flush() {
  while (fd_ >= 0 && out_head_ < out_.size()) {
    ssize_t n = ::send(fd_, out_.data() + out_head_, out_.size() - out_head_, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n > 0) {
      out_head_ += size_t(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    return close("connection to " + remote_text_ + " lost: " + strerror(errno));
  }
  bool drained = out_head_ == out_.size();
  if (drained) {
    out_.clear();
    out_head_ = 0;
  }
  uint32_t want = EPOLLIN | (drained ? 0u : uint32_t(EPOLLOUT));
  if (fd_ >= 0 && want != events_) {
    events_ = want;
    loop_.modify(fd_, want);
  }
  if (drained && state_ == LinkState::Up) listener_.on_link_writable();
}

void RemoteLink::read_some() {
  for (int round = 0; round < 16 && fd_ >= 0; ++round) {
    std::span<uint8_t> space = reader_.write_space(16 * 1024);
    ssize_t n = recv(fd_, space.data(), space.size(), MSG_DONTWAIT);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno != EAGAIN && errno != EWOULDBLOCK)
        close("connection to " + remote_text_ + " lost: " + strerror(errno));
      return;
    }
    if (n == 0) return close("remote " + remote_text_ + " closed the connection");
    last_rx_us_ = loop_.now_us();
    reader_.commit(size_t(n));
    for (std::span<const uint8_t> frame = reader_.next(); !frame.empty() && fd_ >= 0;
         frame = reader_.next()) {
      dispatch(frame);
    }
    if (fd_ >= 0 && reader_.too_large()) {
      return close("remote sent a frame of " + std::to_string(reader_.announced_bytes()) +
                   " bytes, over the limit");
    }
  }
}

void RemoteLink::dispatch(std::span<const uint8_t> frame) {
  wire::VerifyError why{};
  const wire::Message* msg = wire::verify_frame(frame, options_.limits, &why);
  if (msg == nullptr)
    return close("bad frame from " + remote_text_ + ": " + std::string(wire::verify_error_text(why)));
  const wire::Header& h = *msg->header();
  switch (h.kind()) {
    case wire::Kind::Hello: {
      const wire::Hello* hello = msg->body_as_Hello();
      if (hello == nullptr || hello->protocol_version() != wire::kProtocolVersion) {
        return close("remote " + remote_text_ + " speaks another protocol version");
      }
      if (state_ != LinkState::Handshake) return;
      disarm(step_timer_);
      set_state(LinkState::Up);
      backoff_us_ = 0;
      ++connections_;
      arm(ping_timer_, options_.idle_timeout_us / 4, options_.idle_timeout_us / 4);
      listener_.on_link_up();
      return;
    }
    case wire::Kind::TimeSync:
      return;  // the keep-alive's reply: last_rx_us_ is all it is for
    case wire::Kind::Error: {
      const wire::Error* e = msg->body_as_Error();
      std::string text = e && e->text() ? e->text()->str() : "no reason given";
      return close("remote " + remote_text_ + " closed the connection: " + text);
    }
    default:
      if (state_ == LinkState::Up) listener_.on_remote_frame(*msg);
  }
}

}  // namespace troupe::drivers::passthrough
