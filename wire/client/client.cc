#include "wire/client/client.h"

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

#include "wire/address.h"
#include "wire/client/proxy.h"
#include "wire/clock.h"

namespace troupe::client {
namespace {

using wire::monotonic_us;

std::string describe_error(const wire::Message& msg) {
  const wire::Error* e = msg.body_as_Error();
  if (e == nullptr) return "refused";
  std::string text = e->text() ? e->text()->str() : std::string();
  return text.empty() ? std::string(wire::EnumNameErrorCode(e->code())) : text;
}

wire::ConnectionOptions connection_options(const std::string& host, uint16_t port, const Client::Options& o) {
  wire::ConnectionOptions c;
  c.name = o.name;
  bool v6 = host.find(':') != std::string::npos && host.front() != '[';
  c.target = (v6 ? "[" + host + "]" : host) + ":" + std::to_string(port);
  c.limits = o.limits;
  c.reconnect = o.reconnect;
  c.backoff_min_us = uint64_t(o.reconnect_min_ms) * 1000u;
  c.backoff_max_us = uint64_t(std::max(o.reconnect_max_ms, o.reconnect_min_ms)) * 1000u;
  c.keepalive_us = uint64_t(o.keepalive_ms) * 1000u;
  c.keepalive_timeout_us = uint64_t(o.keepalive_timeout_ms) * 1000u;
  return c;
}

}  // namespace

std::string DeviceEntry::text() const { return wire::format_address(addr, robot_name); }

Client::Client(std::string host, uint16_t port) : Client(std::move(host), port, Options{}) {}

Client::Client(std::string host, uint16_t port, Options options)
    : host_(std::move(host)),
      options_(std::move(options)),
      link_(host_, port, connection_options(host_, port, options_), options_.resolver, options_.transport.get()) {
  if (options_.udp_data && options_.transport == nullptr) open_udp();
}

Client::~Client() {
  for (Proxy* p : proxies_) p->client_ = nullptr;
  if (udp_fd_ >= 0) ::close(udp_fd_);
}

bool Client::connected() const { return link_.connection().up(); }

void Client::open_udp() {
  // One socket for both families (IPv6 with IPv4-mapped addresses), so it
  // serves whichever address of the host the connection ends up on.
  sockaddr_in6 any6{};
  any6.sin6_family = AF_INET6;
  udp_fd_ = socket(AF_INET6, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  int off = 0;
  if (udp_fd_ >= 0 && (setsockopt(udp_fd_, IPPROTO_IPV6, IPV6_V6ONLY, &off, sizeof off) != 0 ||
                       bind(udp_fd_, reinterpret_cast<sockaddr*>(&any6), sizeof any6) != 0)) {
    ::close(udp_fd_);
    udp_fd_ = -1;
  }
  if (udp_fd_ < 0) {  // a host without IPv6
    sockaddr_in any4{};
    any4.sin_family = AF_INET;
    udp_fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (udp_fd_ >= 0 && bind(udp_fd_, reinterpret_cast<sockaddr*>(&any4), sizeof any4) != 0) {
      ::close(udp_fd_);
      udp_fd_ = -1;
    }
  }
  sockaddr_storage bound{};
  socklen_t len = sizeof bound;
  if (udp_fd_ < 0 || getsockname(udp_fd_, reinterpret_cast<sockaddr*>(&bound), &len) != 0) return;
  uint16_t port = ntohs(bound.ss_family == AF_INET6 ? reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port
                                                    : reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
  link_.connection().set_udp_port(port);
}

bool Client::connect(int timeout_ms) {
  if (state() == wire::LinkState::Idle || state() == wire::LinkState::Waiting) link_.start();
  dispatch_events();
  uint64_t deadline = monotonic_us() + uint64_t(std::max(timeout_ms, 0)) * 1000u;
  // Connected means the TimeSync sent with the Hello has come back too:
  // clock_offset_us() is valid when this returns true.
  auto pending = [&] {
    wire::LinkState s = state();
    return s == wire::LinkState::Connecting || s == wire::LinkState::Handshake ||
           (s == wire::LinkState::Up && !link_.connection().clock_synced());
  };
  while (pending()) {
    uint64_t now = monotonic_us();
    if (now >= deadline) {
      error_ = "timed out connecting to " + link_.connection().options().target;
      return false;
    }
    spin_once(int((deadline - now + 999) / 1000));
  }
  return connected();
}

void Client::on_up() {
  // Devices opened before a reconnect are opened again; their Acks need no
  // waiting (a Nack shows up in error()).
  for (const Opened& o : opened_) {
    auto& ob = control_writer_.start();
    auto open = wire::CreateOpen(ob, o.access, o.delivery, o.compression);
    queue(control_writer_.finish(wire::make_header(o.addr, wire::Kind::Open, 0, next_seq(), monotonic_us()),
                                 wire::Body::Open, open.Union()));
  }
}

void Client::on_down(std::string_view why) {
  error_ = why;
  if (awaited_seq_ != 0 && !awaited_done_) {
    awaited_ = Reply{};
    awaited_.status = Reply::Status::Disconnected;
    awaited_.text = why;
    awaited_done_ = true;
  }
}

int Client::poll_fds(pollfd* fds, int max) const {
  int n = link_.poll_fds(fds, max);
  // Datagrams come only on an established connection; while two attempts
  // are in flight this keeps the set at two.
  if (udp_fd_ >= 0 && link_.fd() >= 0 && n < max) fds[n++] = pollfd{udp_fd_, POLLIN, 0};
  return n;
}

int Client::next_timeout_ms() const { return link_.next_timeout_ms(); }

void Client::process(const pollfd* fds, int n) {
  link_.process(fds, n);
  for (int i = 0; i < n; ++i) {
    if (udp_fd_ >= 0 && fds[i].fd == udp_fd_ && (fds[i].revents & POLLIN)) read_udp();
  }
  dispatch_events();
}

bool Client::spin_once(int timeout_ms) {
  dispatch_events();
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
  uint64_t deadline = monotonic_us() + uint64_t(std::max(ms, 0)) * 1000u;
  for (uint64_t now = monotonic_us(); now < deadline; now = monotonic_us()) spin_once(int((deadline - now + 999) / 1000));
}

void Client::read_udp() {
  uint8_t buf[65536];
  for (;;) {
    ssize_t n = recv(udp_fd_, buf, sizeof buf, MSG_DONTWAIT);
    if (n <= 0) return;
    const wire::Message* msg = wire::verify_frame({buf, size_t(n)}, options_.limits);
    // Only Data travels by datagram; anything else is noise.
    if (msg != nullptr && msg->header()->kind() == wire::Kind::Data) on_frame({buf, size_t(n)}, *msg);
  }
}

void Client::dispatch_events() {
  for (wire::Event e = link_.next_event(); e.kind != wire::EventKind::None; e = link_.next_event()) {
    switch (e.kind) {
      case wire::EventKind::Up: on_up(); break;
      case wire::EventKind::Down: on_down(e.text); break;
      case wire::EventKind::Synced:
      case wire::EventKind::Frame: on_frame(e.frame, *e.message); break;
      case wire::EventKind::None: break;
    }
  }
}

void Client::on_frame(std::span<const uint8_t> frame, const wire::Message& msg) {
  const wire::Header& h = *msg.header();
  switch (h.kind()) {
    case wire::Kind::Data:
      for (Proxy* p : proxies_) {
        if (p->address() == h.addr()) p->receive(msg);
      }
      for (auto& [id, handler] : handlers_) handler(msg);
      break;
    case wire::Kind::TimeSync:
    case wire::Kind::Ack:
    case wire::Kind::Nack:
    case wire::Kind::DeviceList:
      if (h.kind() == wire::Kind::Nack) error_ = describe_error(msg);
      if (awaited_seq_ != 0 && h.seq() == awaited_seq_ && !awaited_done_) {
        awaited_ = Reply{};
        awaited_.status = h.kind() == wire::Kind::Nack ? Reply::Status::Nack : Reply::Status::Ack;
        awaited_.frame.assign(frame.begin(), frame.end());
        if (h.kind() == wire::Kind::Nack) {
          const wire::Error* e = msg.body_as_Error();
          awaited_.code = e ? e->code() : wire::ErrorCode::Unknown;
          awaited_.text = error_;
        }
        awaited_done_ = true;
      }
      break;
    default: break;
  }
}

bool Client::queue(std::span<const uint8_t> frame) {
  if (!link_.send(frame)) {
    if (!connected()) error_ = "not connected to " + host_;
    return false;
  }
  return true;
}

bool Client::send_frame(std::span<const uint8_t> frame) { return queue(frame); }

bool Client::send_simple(const wire::Address& addr, wire::Kind kind, uint32_t seq, wire::Body type,
                         flatbuffers::Offset<void> body) {
  return queue(writer_.finish(wire::make_header(addr, kind, 0, seq, monotonic_us()), type, body));
}

Reply Client::wait_reply(uint32_t seq, int timeout_ms) {
  awaited_seq_ = seq;
  awaited_done_ = false;
  uint64_t deadline = monotonic_us() + uint64_t(std::max(timeout_ms, 0)) * 1000u;
  while (!awaited_done_) {
    uint64_t now = monotonic_us();
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
  return queue(writer_.finish(wire::make_header(addr, wire::Kind::Command, subtype, next_seq(), monotonic_us()), type,
                              body));
}

Reply Client::request(const wire::Address& addr, uint8_t subtype, wire::Body type, flatbuffers::Offset<void> body,
                      int timeout_ms) {
  uint32_t seq = next_seq();
  if (!queue(writer_.finish(wire::make_header(addr, wire::Kind::Request, subtype, seq, monotonic_us()), type, body))) {
    Reply r;
    r.status = Reply::Status::Disconnected;
    r.text = "not connected to " + host_;
    error_ = r.text;
    return r;
  }
  return wait_reply(seq, timeout_ms);
}

bool Client::sync(int timeout_ms) {
  uint32_t seq = link_.request_time_sync();
  if (seq == 0) {
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

bool Client::open(const wire::Address& addr, wire::Access access, wire::Delivery delivery,
                  wire::ImageCompression compression, int timeout_ms) {
  auto it = std::find_if(opened_.begin(), opened_.end(), [&](const Opened& o) { return o.addr == addr; });
  if (it == opened_.end()) {
    opened_.push_back({addr, access, delivery, compression});
  } else {
    it->access = access;
    it->delivery = delivery;
    it->compression = compression;
  }
  uint32_t seq = next_seq();
  auto& b = writer_.start();
  auto body = wire::CreateOpen(b, access, delivery, compression);
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
