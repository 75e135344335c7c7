#include "wire/client/client.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>

#include "wire/address.h"
#include "wire/client/proxy.h"

namespace troupe::client {
namespace {

uint64_t now_us() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return uint64_t(ts.tv_sec) * 1000000u + uint64_t(ts.tv_nsec) / 1000u;
}

std::string describe_error(const wire::Message& msg) {
  const wire::Error* e = msg.body_as_Error();
  if (e == nullptr) return "refused";
  std::string text = e->text() ? e->text()->str() : std::string();
  return text.empty() ? std::string(wire::EnumNameErrorCode(e->code())) : text;
}

}  // namespace

std::string DeviceEntry::text() const { return wire::format_address(addr, robot_name); }

Client::Client(std::string host, uint16_t port) : Client(std::move(host), port, Options{}) {}

Client::Client(std::string host, uint16_t port, Options options)
    : host_(std::move(host)), port_(port), options_(std::move(options)), reader_(options_.limits.max_frame_bytes) {}

Client::~Client() {
  for (Proxy* p : proxies_) p->client_ = nullptr;
  if (fd_ >= 0) ::close(fd_);
  if (udp_fd_ >= 0) ::close(udp_fd_);
}

bool Client::connected() const { return state_ == State::Connected; }

bool Client::connect(int timeout_ms) {
  if (state_ == State::Idle && !start_connect()) return false;
  uint64_t deadline = now_us() + uint64_t(std::max(timeout_ms, 0)) * 1000u;
  // Connected means the TimeSync sent with the handshake has come back
  // too: clock_offset_us() is valid when this returns true.
  while (state_ == State::Connecting || state_ == State::Handshake || (connected() && !time_synced_)) {
    uint64_t now = now_us();
    if (now >= deadline) {
      error_ = "timed out connecting to " + host_ + ":" + std::to_string(port_);
      return false;
    }
    spin_once(int((deadline - now + 999) / 1000));
  }
  return connected();
}

bool Client::start_connect() {
  reconnect_at_us_ = 0;
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_NUMERICSERV;
  addrinfo* found = nullptr;
  std::string port_text = std::to_string(port_);
  int rc = getaddrinfo(host_.c_str(), port_text.c_str(), &hints, &found);
  if (rc != 0) {
    error_ = "cannot resolve host '" + host_ + "': " + gai_strerror(rc);
    schedule_reconnect();
    return false;
  }
  int last_errno = 0;
  for (addrinfo* ai = found; ai != nullptr; ai = ai->ai_next) {
    int fd = socket(ai->ai_family, ai->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, ai->ai_protocol);
    if (fd < 0) continue;
    int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    if (::connect(fd, ai->ai_addr, ai->ai_addrlen) == 0 || errno == EINPROGRESS) {
      fd_ = fd;
      break;
    }
    last_errno = errno;
    ::close(fd);
  }
  int family = found ? found->ai_family : AF_INET;
  freeaddrinfo(found);
  if (fd_ < 0) {
    error_ = "cannot connect to " + host_ + ":" + port_text + ": " + strerror(last_errno);
    schedule_reconnect();
    return false;
  }
  if (options_.udp_data && udp_fd_ < 0) {
    udp_fd_ = socket(family, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    sockaddr_storage any{};
    any.ss_family = sa_family_t(family);
    socklen_t len = family == AF_INET6 ? sizeof(sockaddr_in6) : sizeof(sockaddr_in);
    if (udp_fd_ >= 0 && bind(udp_fd_, reinterpret_cast<sockaddr*>(&any), len) == 0 &&
        getsockname(udp_fd_, reinterpret_cast<sockaddr*>(&any), &len) == 0) {
      udp_port_ = ntohs(family == AF_INET6 ? reinterpret_cast<sockaddr_in6*>(&any)->sin6_port
                                           : reinterpret_cast<sockaddr_in*>(&any)->sin_port);
    }
  }
  state_ = State::Connecting;
  return true;
}

void Client::on_connected() {
  state_ = State::Handshake;
  hello_seen_ = false;
  time_synced_ = false;
  auto& b = control_writer_.start();
  auto hello = wire::CreateHello(b, wire::kProtocolVersion, b.CreateString(options_.name),
                                 options_.limits.max_frame_bytes, udp_port_, now_us());
  queue(control_writer_.finish(wire::make_header({}, wire::Kind::Hello, 0, 0, now_us()), wire::Body::Hello,
                               hello.Union()));
  time_sync_seq_ = next_seq();
  auto& t = control_writer_.start();
  auto sync = wire::CreateTimeSync(t, now_us(), 0, 0);
  queue(control_writer_.finish(wire::make_header({}, wire::Kind::TimeSync, 0, time_sync_seq_, now_us()),
                               wire::Body::TimeSync, sync.Union()));
  // Devices opened before a reconnect are opened again; their Acks need no
  // waiting (a Nack shows up in error()).
  for (const Opened& o : opened_) {
    auto& ob = control_writer_.start();
    auto open = wire::CreateOpen(ob, o.access, o.delivery);
    queue(control_writer_.finish(wire::make_header(o.addr, wire::Kind::Open, 0, next_seq(), now_us()),
                                 wire::Body::Open, open.Union()));
  }
}

void Client::disconnect(const std::string& why) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  state_ = State::Idle;
  error_ = why;
  reader_ = wire::FrameReader(options_.limits.max_frame_bytes);
  out_.clear();
  out_head_ = 0;
  if (awaited_seq_ != 0 && !awaited_done_) {
    awaited_ = Reply{};
    awaited_.status = Reply::Status::Disconnected;
    awaited_.text = why;
    awaited_done_ = true;
  }
  schedule_reconnect();
}

void Client::schedule_reconnect() {
  if (!options_.reconnect) return;
  backoff_ms_ = backoff_ms_ == 0 ? options_.reconnect_min_ms : std::min(backoff_ms_ * 2, options_.reconnect_max_ms);
  reconnect_at_us_ = now_us() + uint64_t(backoff_ms_) * 1000u;
}

int Client::poll_fds(pollfd* fds, int max) const {
  int n = 0;
  if (fd_ >= 0 && n < max) {
    short events = POLLIN;
    if (state_ == State::Connecting || out_head_ < out_.size()) events |= POLLOUT;
    fds[n++] = pollfd{fd_, events, 0};
  }
  if (udp_fd_ >= 0 && n < max) fds[n++] = pollfd{udp_fd_, POLLIN, 0};
  return n;
}

int Client::next_timeout_ms() const {
  if (state_ != State::Idle || reconnect_at_us_ == 0) return -1;
  uint64_t now = now_us();
  return reconnect_at_us_ > now ? int((reconnect_at_us_ - now + 999) / 1000) : 0;
}

void Client::process(const pollfd* fds, int n) {
  for (int i = 0; i < n; ++i) {
    if (fds[i].revents == 0) continue;
    if (fds[i].fd == fd_ && fd_ >= 0) {
      if (state_ == State::Connecting) {
        int err = 0;
        socklen_t len = sizeof err;
        getsockopt(fd_, SOL_SOCKET, SO_ERROR, &err, &len);
        if (err != 0) {
          disconnect("cannot connect to " + host_ + ":" + std::to_string(port_) + ": " + strerror(err));
          continue;
        }
        on_connected();
      }
      if (fds[i].revents & POLLOUT) flush();
      if (fd_ >= 0 && (fds[i].revents & (POLLIN | POLLHUP | POLLERR))) read_tcp();
    } else if (fds[i].fd == udp_fd_ && (fds[i].revents & POLLIN)) {
      read_udp();
    }
  }
  if (state_ == State::Idle && reconnect_at_us_ != 0 && now_us() >= reconnect_at_us_) start_connect();
}

bool Client::spin_once(int timeout_ms) {
  pollfd fds[2];
  int n = poll_fds(fds, 2);
  int wait = timeout_ms;
  int timer = next_timeout_ms();
  if (timer >= 0 && (wait < 0 || timer < wait)) wait = timer;
  if (n == 0 && wait < 0) return false;
  int rc = poll(fds, nfds_t(n), wait);
  if (rc < 0 && errno != EINTR) return false;
  bool had_input = false;
  for (int i = 0; i < n; ++i) had_input |= (fds[i].revents & POLLIN) != 0;
  process(fds, n);
  return had_input;
}

void Client::spin_for(int ms) {
  uint64_t deadline = now_us() + uint64_t(std::max(ms, 0)) * 1000u;
  for (uint64_t now = now_us(); now < deadline; now = now_us()) spin_once(int((deadline - now + 999) / 1000));
}

void Client::read_tcp() {
  for (int round = 0; round < 16 && fd_ >= 0; ++round) {
    std::span<uint8_t> space = reader_.write_space(16 * 1024);
    ssize_t n = recv(fd_, space.data(), space.size(), MSG_DONTWAIT);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno != EAGAIN && errno != EWOULDBLOCK) disconnect("connection to " + host_ + " lost: " + strerror(errno));
      return;
    }
    if (n == 0) {
      // Keep the node's own explanation if it sent one before closing.
      disconnect(error_.rfind("node closed", 0) == 0 ? error_ : "connection to " + host_ + " closed by the node");
      return;
    }
    reader_.commit(size_t(n));
    for (;;) {
      std::span<const uint8_t> frame = reader_.next();
      if (frame.empty()) break;
      dispatch(frame);
      if (fd_ < 0) return;
    }
    if (reader_.too_large()) {
      disconnect("node sent a frame over the limit (" + std::to_string(reader_.announced_bytes()) + " bytes)");
      return;
    }
  }
}

void Client::read_udp() {
  uint8_t buf[65536];
  for (;;) {
    ssize_t n = recv(udp_fd_, buf, sizeof buf, MSG_DONTWAIT);
    if (n <= 0) return;
    const wire::Message* msg = wire::verify_frame({buf, size_t(n)}, options_.limits);
    // Only Data travels by datagram; anything else is noise.
    if (msg != nullptr && msg->header()->kind() == wire::Kind::Data) dispatch({buf, size_t(n)});
  }
}

void Client::dispatch(std::span<const uint8_t> frame) {
  wire::VerifyError why{};
  const wire::Message* msg = wire::verify_frame(frame, options_.limits, &why);
  if (msg == nullptr) {
    disconnect("bad frame from the node: " + std::string(wire::verify_error_text(why)));
    return;
  }
  const wire::Header& h = *msg->header();
  switch (h.kind()) {
    case wire::Kind::Hello: {
      const wire::Hello* hello = msg->body_as_Hello();
      if (hello == nullptr) break;
      if (hello->protocol_version() != wire::kProtocolVersion) {
        disconnect("node speaks protocol " + std::to_string(hello->protocol_version()) + ", this client " +
                   std::to_string(wire::kProtocolVersion));
        return;
      }
      node_name_ = hello->name() ? hello->name()->str() : std::string();
      state_ = State::Connected;
      ++connections_;
      backoff_ms_ = 0;
      break;
    }
    case wire::Kind::Data:
      for (Proxy* p : proxies_) {
        if (p->address() == h.addr()) p->receive(*msg);
      }
      for (auto& [id, handler] : handlers_) handler(*msg);
      break;
    case wire::Kind::TimeSync:
      if (awaited_seq_ != 0 && h.seq() == awaited_seq_) {
        awaited_ = Reply{};
        awaited_.status = Reply::Status::Ack;
        awaited_.frame.assign(frame.begin(), frame.end());
        awaited_done_ = true;
      }
      if (h.seq() == time_sync_seq_ || h.seq() == awaited_seq_) {
        if (const wire::TimeSync* t = msg->body_as_TimeSync()) {
          int64_t t0 = int64_t(t->client_send_us()), t1 = int64_t(t->node_recv_us());
          int64_t t2 = int64_t(t->node_send_us()), t3 = int64_t(now_us());
          clock_offset_us_ = ((t1 - t0) + (t2 - t3)) / 2;
        }
        time_synced_ = true;
      }
      break;
    case wire::Kind::Ack:
    case wire::Kind::Nack:
    case wire::Kind::DeviceList:
      if (h.kind() == wire::Kind::Nack) error_ = describe_error(*msg);
      if (awaited_seq_ != 0 && h.seq() == awaited_seq_ && !awaited_done_) {
        awaited_ = Reply{};
        awaited_.status = h.kind() == wire::Kind::Nack ? Reply::Status::Nack : Reply::Status::Ack;
        awaited_.frame.assign(frame.begin(), frame.end());
        if (h.kind() == wire::Kind::Nack) {
          const wire::Error* e = msg->body_as_Error();
          awaited_.code = e ? e->code() : wire::ErrorCode::Unknown;
          awaited_.text = error_;
        }
        awaited_done_ = true;
      }
      break;
    case wire::Kind::Error:
      // The node closes the connection after an Error; remember why.
      error_ = "node closed the connection: " + describe_error(*msg);
      break;
    default: break;
  }
}

void Client::flush() {
  if (fd_ < 0 || state_ == State::Connecting) return;
  while (out_head_ < out_.size()) {
    ssize_t n = send(fd_, out_.data() + out_head_, out_.size() - out_head_, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n > 0) {
      out_head_ += size_t(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;
    disconnect("connection to " + host_ + " lost: " + strerror(errno));
    return;
  }
  out_.clear();
  out_head_ = 0;
}

bool Client::queue(std::span<const uint8_t> frame) {
  if (state_ == State::Idle) return false;
  if (out_head_ > 0 && out_head_ >= out_.size() / 2) {
    out_.erase(out_.begin(), out_.begin() + long(out_head_));
    out_head_ = 0;
  }
  out_.insert(out_.end(), frame.begin(), frame.end());
  flush();
  return fd_ >= 0;
}

bool Client::send_frame(std::span<const uint8_t> frame) { return queue(frame); }

bool Client::send_simple(const wire::Address& addr, wire::Kind kind, uint32_t seq, wire::Body type,
                         flatbuffers::Offset<void> body) {
  return queue(writer_.finish(wire::make_header(addr, kind, 0, seq, now_us()), type, body));
}

Reply Client::wait_reply(uint32_t seq, int timeout_ms) {
  awaited_seq_ = seq;
  awaited_done_ = false;
  uint64_t deadline = now_us() + uint64_t(std::max(timeout_ms, 0)) * 1000u;
  while (!awaited_done_) {
    uint64_t now = now_us();
    if (now >= deadline) break;
    spin_once(int((deadline - now + 999) / 1000));
  }
  Reply reply;
  if (awaited_done_) {
    reply = std::move(awaited_);
  } else {
    reply.status = Reply::Status::Timeout;
    reply.text = "no reply within " + std::to_string(timeout_ms) + " ms";
    error_ = reply.text;
  }
  awaited_seq_ = 0;
  awaited_done_ = false;
  return reply;
}

bool Client::command(const wire::Address& addr, uint8_t subtype, wire::Body type, flatbuffers::Offset<void> body) {
  if (state_ == State::Idle) {
    error_ = "not connected to " + host_;
    return false;
  }
  return queue(writer_.finish(wire::make_header(addr, wire::Kind::Command, subtype, next_seq(), now_us()), type,
                              body));
}

Reply Client::request(const wire::Address& addr, uint8_t subtype, wire::Body type, flatbuffers::Offset<void> body,
                      int timeout_ms) {
  uint32_t seq = next_seq();
  if (state_ == State::Idle ||
      !queue(writer_.finish(wire::make_header(addr, wire::Kind::Request, subtype, seq, now_us()), type, body))) {
    Reply r;
    r.status = Reply::Status::Disconnected;
    r.text = "not connected to " + host_;
    error_ = r.text;
    return r;
  }
  return wait_reply(seq, timeout_ms);
}

bool Client::sync(int timeout_ms) {
  uint32_t seq = next_seq();
  auto& b = writer_.start();
  auto body = wire::CreateTimeSync(b, now_us(), 0, 0);
  if (!send_simple({}, wire::Kind::TimeSync, seq, wire::Body::TimeSync, body.Union())) {
    error_ = "not connected to " + host_;
    return false;
  }
  return wait_reply(seq, timeout_ms).ok();
}

bool Client::device_list(std::vector<DeviceEntry>& out, int timeout_ms) {
  uint32_t seq = next_seq();
  if (!send_simple({}, wire::Kind::DeviceList, seq)) {
    error_ = "not connected to " + host_;
    return false;
  }
  Reply r = wait_reply(seq, timeout_ms);
  const wire::Message* msg = r.message();
  const wire::DeviceList* list = msg ? msg->body_as_DeviceList() : nullptr;
  if (!r.ok() || list == nullptr) return false;
  out.clear();
  if (list->devices() == nullptr) return true;
  for (const wire::DeviceInfo* d : *list->devices()) {
    if (d->addr() == nullptr) continue;
    out.push_back({*d->addr(), d->robot_name() ? d->robot_name()->str() : "", d->driver() ? d->driver()->str() : ""});
  }
  return true;
}

bool Client::resolve(std::string_view spec, wire::Address& out, int timeout_ms) {
  wire::DeviceSpec parsed;
  if (!wire::parse_device(spec, parsed, error_)) return false;
  int robot = wire::robot_number(parsed.robot);
  if (robot < 0) {
    std::vector<DeviceEntry> devices;
    if (!device_list(devices, timeout_ms)) return false;
    for (const DeviceEntry& d : devices) {
      if (d.robot_name == parsed.robot) {
        robot = d.addr.robot();
        break;
      }
    }
    if (robot < 0) {
      error_ = "no robot named '" + parsed.robot + "' on " + host_;
      return false;
    }
  }
  out = wire::Address(uint16_t(robot), uint16_t(parsed.iface), parsed.index);
  return true;
}

bool Client::open(const wire::Address& addr, wire::Access access, wire::Delivery delivery, int timeout_ms) {
  auto it = std::find_if(opened_.begin(), opened_.end(), [&](const Opened& o) { return o.addr == addr; });
  if (it == opened_.end()) {
    opened_.push_back({addr, access, delivery});
  } else {
    it->access = access;
    it->delivery = delivery;
  }
  uint32_t seq = next_seq();
  auto& b = writer_.start();
  auto body = wire::CreateOpen(b, access, delivery);
  if (!send_simple(addr, wire::Kind::Open, seq, wire::Body::Open, body.Union())) {
    error_ = "not connected to " + host_;
    return false;
  }
  return wait_reply(seq, timeout_ms).ok();
}

bool Client::close(const wire::Address& addr, int timeout_ms) {
  std::erase_if(opened_, [&](const Opened& o) { return o.addr == addr; });
  uint32_t seq = next_seq();
  if (!send_simple(addr, wire::Kind::Close, seq)) return false;
  return wait_reply(seq, timeout_ms).ok();
}

bool Client::pull(const wire::Address& addr, int timeout_ms) {
  uint32_t seq = next_seq();
  if (!send_simple(addr, wire::Kind::Pull, seq)) {
    error_ = "not connected to " + host_;
    return false;
  }
  return wait_reply(seq, timeout_ms).ok();
}

int Client::add_data_handler(DataHandler handler) {
  handlers_.emplace_back(next_handler_id_, std::move(handler));
  return next_handler_id_++;
}

void Client::remove_data_handler(int id) {
  std::erase_if(handlers_, [id](const auto& h) { return h.first == id; });
}

void Client::add_proxy(Proxy* proxy) { proxies_.push_back(proxy); }
void Client::remove_proxy(Proxy* proxy) { std::erase(proxies_, proxy); }

}  // namespace troupe::client
