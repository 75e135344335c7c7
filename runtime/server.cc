#include "runtime/server.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "runtime/log.h"
#include "runtime/node.h"

namespace troupe {
namespace {

// How long a connection closed for an error may take to read that error
// before it is cut, us.
constexpr uint64_t kLingerUs = 2'000'000;
// Reads per readiness event: a busy client cannot starve the others.
constexpr int kReadsPerEvent = 8;
constexpr size_t kReadChunk = 16 * 1024;
// Largest UDP payload; bigger data goes over TCP.
constexpr size_t kMaxDatagram = 65507;
// Room kept for the tail of a data frame the socket took only part of; a
// larger frame grows it once.
constexpr size_t kPartialReserve = 4096;

bool set_nonblocking(int fd) {
  int flags = fcntl(fd, F_GETFL, 0);
  return flags >= 0 && fcntl(fd, F_SETFL, flags | O_NONBLOCK) == 0;
}

// An Error frame answering `about` (its address, subtype and seq), or
// nothing in particular.
std::span<const uint8_t> error_frame(wire::MessageWriter& w, const wire::Header* about, wire::ErrorCode code,
                                     std::string_view text, uint64_t now_us) {
  auto& b = w.start();
  auto body = wire::CreateError(b, code, b.CreateString(text.data(), text.size()));
  wire::Header h = about ? wire::make_header(about->addr(), wire::Kind::Error, about->subtype(), about->seq(), now_us)
                         : wire::make_header({}, wire::Kind::Error, 0, 0, now_us);
  return w.finish(h, wire::Body::Error, body.Union());
}


}  // namespace

void Server::send_error_now(int fd, wire::ErrorCode code, std::string_view text) {
  wire::MessageWriter w(256);
  auto frame = error_frame(w, nullptr, code, text, node_.now_us());
  (void)!send(fd, frame.data(), frame.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
}

Server::Server(Node& node) : node_(node), clients_(node.options().max_clients) {}

Server::~Server() {
  close_all();
  close_listeners();
}

void Server::close_listeners() {
  for (int i = 0; i < listener_count_; ++i) {
    if (listeners_[i].tcp >= 0) {
      node_.loop().unwatch(listeners_[i].tcp);
      close(listeners_[i].tcp);
    }
    if (listeners_[i].udp >= 0) close(listeners_[i].udp);
    listeners_[i] = Listener{};
  }
  listener_count_ = 0;
}

// Binds and listens on one address; on success fills `out` (and its UDP
// data socket when UDP is on) and returns 0, else the errno.
int Server::listen_on(const sockaddr* addr, socklen_t len, bool v6_only, Listener& out) {
  int fd = socket(addr->sa_family, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return errno;
  int one = 1;
  setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  // The IPv6 half of a pair must leave IPv4 to its own socket.
  if (v6_only) setsockopt(fd, IPPROTO_IPV6, IPV6_V6ONLY, &one, sizeof one);
  if (bind(fd, addr, len) != 0 || listen(fd, 64) != 0 || !set_nonblocking(fd)) {
    int err = errno;
    close(fd);
    return err;
  }
  out = Listener{fd, -1, addr->sa_family};
  sockaddr_storage bound{};
  socklen_t bound_len = sizeof bound;
  getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &bound_len);
  port_ = ntohs(bound.ss_family == AF_INET6 ? reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port
                                            : reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
  if (node_.options().udp) {
    // Data datagrams leave from the same address and port number.
    int ufd = socket(addr->sa_family, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (ufd >= 0 && v6_only) setsockopt(ufd, IPPROTO_IPV6, IPV6_V6ONLY, &one, sizeof one);
    if (ufd >= 0 && bind(ufd, reinterpret_cast<sockaddr*>(&bound), bound_len) == 0) {
      out.udp = ufd;
    } else {
      if (ufd >= 0) close(ufd);
      log_warn("UDP data disabled: cannot bind UDP port %u: %s", unsigned(port_), strerror(errno));
    }
  }
  return 0;
}

std::string Server::listen_text() const {
  std::string text;
  for (int i = 0; i < listener_count_; ++i) {
    sockaddr_storage a{};
    socklen_t len = sizeof a;
    char ip[INET6_ADDRSTRLEN] = "?";
    getsockname(listeners_[i].tcp, reinterpret_cast<sockaddr*>(&a), &len);
    bool v6 = a.ss_family == AF_INET6;
    inet_ntop(a.ss_family, v6 ? static_cast<void*>(&reinterpret_cast<sockaddr_in6*>(&a)->sin6_addr)
                              : static_cast<void*>(&reinterpret_cast<sockaddr_in*>(&a)->sin_addr),
              ip, sizeof ip);
    text += std::string(i ? " and " : "") + (v6 ? "[" : "") + ip + (v6 ? "]:" : ":") + std::to_string(port_);
  }
  return text;
}

int Server::udp_for(int family) const {
  for (int i = 0; i < listener_count_; ++i) {
    if (listeners_[i].family == family) return listeners_[i].udp;
  }
  return -1;
}

bool Server::start(std::string& error) {
  const Node::Options& opt = node_.options();
  std::string host = opt.listen;
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  char port_text[8];
  snprintf(port_text, sizeof port_text, "%u", unsigned(opt.port));
  if (host == "localhost") {
    // Both loopbacks, whatever the hosts file says: clients resolve
    // localhost to ::1 first on a standard Debian, to 127.0.0.1 elsewhere.
    sockaddr_in v4{};
    v4.sin_family = AF_INET;
    v4.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    sockaddr_in6 v6{};
    v6.sin6_family = AF_INET6;
    v6.sin6_addr = in6addr_loopback;
    // With port 0 the kernel picks IPv4's port, which may be taken on ::1:
    // then both are tried again with another.
    for (int attempt = 0; attempt < 16; ++attempt) {
      v4.sin_port = htons(opt.port);
      if (int err = listen_on(reinterpret_cast<sockaddr*>(&v4), sizeof v4, false, listeners_[0]); err != 0) {
        error = "cannot listen on 127.0.0.1:" + std::string(port_text) + ": " + strerror(err);
        return false;
      }
      listener_count_ = 1;
      v6.sin6_port = htons(port_);
      int err = listen_on(reinterpret_cast<sockaddr*>(&v6), sizeof v6, true, listeners_[1]);
      if (err == 0) {
        listener_count_ = 2;
        break;
      }
      if (err == EADDRNOTAVAIL || err == EAFNOSUPPORT) {
        log_warn("no IPv6 loopback (%s): serving localhost on 127.0.0.1 only", strerror(err));
        break;
      }
      close_listeners();
      if (err != EADDRINUSE || opt.port != 0) {
        error = "cannot listen on [::1]:" + std::string(port_text) + ": " + strerror(err);
        return false;
      }
    }
    if (listener_count_ == 0) {
      error = "cannot find a port free on both 127.0.0.1 and ::1";
      return false;
    }
  } else {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
    addrinfo* found = nullptr;
    int rc = getaddrinfo(host.empty() ? nullptr : host.c_str(), port_text, &hints, &found);
    if (rc != 0) {
      error = "cannot resolve listen address '" + opt.listen + "': " + gai_strerror(rc);
      return false;
    }
    int last_errno = 0;
    for (addrinfo* ai = found; ai != nullptr && listener_count_ == 0; ai = ai->ai_next) {
      last_errno = listen_on(ai->ai_addr, ai->ai_addrlen, false, listeners_[0]);
      if (last_errno == 0) listener_count_ = 1;
    }
    freeaddrinfo(found);
    if (listener_count_ == 0) {
      error = "cannot listen on " + opt.listen + ":" + port_text + ": " + strerror(last_errno);
      return false;
    }
  }
  for (int i = 0; i < listener_count_; ++i) node_.loop().watch(listeners_[i].tcp, EPOLLIN, this);
  const uint64_t period_us = sweep_period_us();
  sweep_ = node_.loop().start_timer(period_us, period_us, this);
  return true;
}

bool Server::alive(uint32_t client, uint32_t generation) const {
  return client < clients_.size() && clients_[client].state == State::Open &&
         clients_[client].generation == generation;
}

uint32_t Server::index_of_fd(int fd) const {
  if (fd < 0 || size_t(fd) >= client_of_fd_.size()) return UINT32_MAX;
  return client_of_fd_[size_t(fd)] - 1;
}

void Server::on_fd(int fd, uint32_t events) {
  for (int i = 0; i < listener_count_; ++i) {
    if (fd == listeners_[i].tcp) return accept_clients(fd);
  }
  uint32_t index = index_of_fd(fd);
  if (index >= clients_.size()) return;
  Client& c = clients_[index];
  if (c.state == State::Draining) {
    // Discard what the peer still sends until it closes: closing with unread
    // input would reset the connection and could destroy our Error frame.
    uint8_t scratch[4096];
    for (;;) {
      ssize_t n = recv(fd, scratch, sizeof scratch, MSG_DONTWAIT);
      if (n > 0) continue;
      if (n < 0 && errno == EINTR) continue;
      if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK)) close_client(index);
      break;
    }
    if (c.state == State::Draining && (events & EPOLLOUT)) flush(index);
    return;
  }
  if (events & EPOLLOUT) flush(index);
  if (c.state == State::Open && (events & (EPOLLIN | EPOLLHUP | EPOLLERR))) read_client(index);
}

void Server::accept_clients(int listen_fd) {
  for (;;) {
    sockaddr_storage peer{};
    socklen_t len = sizeof peer;
    int fd = accept4(listen_fd, reinterpret_cast<sockaddr*>(&peer), &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
      if (errno == EINTR) continue;
      if (errno != EAGAIN && errno != EWOULDBLOCK) log_warn("accept: %s", strerror(errno));
      return;
    }
    int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    if (int sndbuf = int(node_.options().socket_send_bytes); sndbuf > 0) {
      setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &sndbuf, sizeof sndbuf);
    }
    uint32_t index = slot_for(peer);
    if (index == UINT32_MAX) {
      char text[64];
      snprintf(text, sizeof text, "too many clients (limit %zu)", clients_.size());
      send_error_now(fd, wire::ErrorCode::Denied, text);
      log_warn("refused a client: %s", text);
      close(fd);
      continue;
    }
    Client& c = clients_[index];
    c.fd = fd;
    c.state = State::Open;
    c.reader = wire::FrameReader(node_.options().limits.max_frame_bytes);
    c.peer = peer;
    c.peer_len = len;
    c.udp_port = 0;
    c.max_frame = 0;
    c.connected_us = node_.loop().now_us();
    c.heard_us = 0;
    c.stalled_us = 0;
    c.written = 0;
    c.taken = 0;
    // Sized now, so that serving the client allocates nothing later.
    c.out.reserve(node_.options().client_queue_bytes);
    c.partial.reserve(kPartialReserve);
    if (size_t(fd) >= client_of_fd_.size()) client_of_fd_.resize(size_t(fd) + 1, 0);
    client_of_fd_[size_t(fd)] = index + 1;
    node_.loop().watch(fd, EPOLLIN, this);
    c.writing = false;
    if (kSessionsMayBeSecure && node_.options().make_transport) {
      c.transport = node_.options().make_transport();
      c.sealed.clear();
      c.transport->begin(c.sealed);  // the node answers: nothing to send yet
      c.raw.resize(kReadChunk);
    }
    log_debug("client %u connected (fd %d)", index, fd);
    node_.send_hello(index);
  }
}

void Server::read_client(uint32_t index) {
  Client& c = clients_[index];
  const wire::Limits& limits = node_.options().limits;
  for (int i = 0; i < kReadsPerEvent && c.state == State::Open; ++i) {
    const bool secure = kSessionsMayBeSecure && c.transport != nullptr;
    std::span<uint8_t> space = secure ? std::span<uint8_t>(c.raw) : c.reader.write_space(kReadChunk);
    ssize_t n = recv(c.fd, space.data(), space.size(), MSG_DONTWAIT);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno != EAGAIN && errno != EWOULDBLOCK) {
        log_debug("client %u: recv: %s", index, strerror(errno));
        close_client(index);
      }
      return;
    }
    if (n == 0) {
      if (c.reader.pending_bytes() > 0) {
        char text[96];
        snprintf(text, sizeof text, "truncated frame: the stream ended after %zu bytes of a frame",
                 c.reader.pending_bytes());
        log_warn("client %u: %s", index, text);
        close_with_error(index, wire::ErrorCode::BadFrame, text);
      } else {
        log_debug("client %u disconnected", index);
        close_client(index);
      }
      return;
    }
    if (!secure) {
      c.reader.commit(size_t(n));
    } else if (!open_secure(index, {space.data(), size_t(n)})) {
      return;
    }
    for (;;) {
      std::span<const uint8_t> frame = c.reader.next();
      if (frame.empty()) {
        if (c.reader.too_large()) {
          char text[96];
          snprintf(text, sizeof text, "frame of %u bytes exceeds the limit of %u bytes",
                   c.reader.announced_bytes(), limits.max_frame_bytes);
          log_warn("client %u: %s", index, text);
          close_with_error(index, wire::ErrorCode::BadFrame, text);
          return;
        }
        break;
      }
      wire::VerifyError why{};
      const wire::Message* msg = wire::verify_frame(frame, limits, &why);
      if (msg == nullptr) {
        std::string_view reason = wire::verify_error_text(why);
        log_warn("client %u: bad frame of %zu bytes: %.*s", index, frame.size(), int(reason.size()),
                 reason.data());
        close_with_error(index, wire::ErrorCode::VerifyFailed, reason, wire::peek_header(frame));
        return;
      }
      c.heard_us = node_.loop().now_us();
      node_.route(index, *msg, frame);
      if (c.state != State::Open) return;
    }
  }
}

bool Server::open_secure(uint32_t index, std::span<const uint8_t> bytes) {
  Client& c = clients_[index];
  const bool was_ready = c.transport->ready();
  c.sealed.clear();
  std::string why;
  if (!c.transport->inbound(bytes, c.reader, c.sealed, why)) {
    // Nothing can reach a peer that failed the handshake or broke the
    // session: no Error frame, the connection just ends.
    log_warn("client %u: secure session refused: %s", index, why.c_str());
    close_client(index);
    return false;
  }
  if (!c.sealed.empty()) {
    // The handshake's answer goes first, before the Hello waiting in out.
    c.partial.insert(c.partial.end(), c.sealed.begin(), c.sealed.end());
  }
  if (!was_ready && c.transport->ready()) {
    const std::string peer = c.transport->peer_identity();
    log_info("client %u: secure session with key %s", index, peer.c_str());
    if (node_.options().rights_of) c.rights = node_.options().rights_of(peer);
  }
  if (!c.sealed.empty() || (!was_ready && c.transport->ready())) flush(index);
  return c.state == State::Open;
}

void Server::handle_hello(uint32_t index, const wire::Message& msg) {
  const wire::Hello* hello = msg.body_as_Hello();  // present: checked by the router
  if (hello->protocol_version() != wire::kProtocolVersion) {
    char text[96];
    snprintf(text, sizeof text, "client speaks protocol %u, this node speaks %u",
             unsigned(hello->protocol_version()), unsigned(wire::kProtocolVersion));
    close_with_error(index, wire::ErrorCode::VersionMismatch, text, msg.header());
    return;
  }
  Client& c = clients_[index];
  c.max_frame = hello->max_frame_bytes();
  if (kSessionsMayBeSecure && hello->udp_port() != 0 && c.transport != nullptr) {
    // Datagrams would travel outside the secure session.
    log_warn("client %u asked for UDP data, but its session is secure; data stays on TCP", index);
  } else if (hello->udp_port() != 0 && udp_for(c.peer.ss_family) < 0) {
    log_warn("client %u asked for UDP data, but UDP is disabled; data stays on TCP", index);
  } else {
    c.udp_port = hello->udp_port();
  }
  log_debug("client %u is '%s'%s", index, hello->name() ? hello->name()->c_str() : "",
            c.udp_port ? " (data over UDP)" : "");
}

long Server::write_some(Client& c, std::span<const uint8_t> bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    ssize_t n = send(c.fd, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n > 0) {
      done += size_t(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    return -1;
  }
  c.written += done;
  return long(done);
}

void Server::want_write(uint32_t index, bool on) {
  Client& c = clients_[index];
  if (c.writing == on) return;
  c.writing = on;
  node_.loop().modify(c.fd, EPOLLIN | (on ? EPOLLOUT : 0u));
}

void Server::flush(uint32_t index) {
  Client& c = clients_[index];
  if (c.state == State::Free) return;
  auto failed = [&] {
    log_debug("client %u: send failed: %s", index, strerror(errno));
    close_client(index);
  };
  // 1. The rest of a data frame the socket took part of.
  if (c.partial_head < c.partial.size()) {
    long n = write_some(c, {c.partial.data() + c.partial_head, c.partial.size() - c.partial_head});
    if (n < 0) return failed();
    c.partial_head += size_t(n);
    if (c.partial_head < c.partial.size()) return want_write(index, true);
  }
  // A secure session's frames wait until its handshake is over.
  if (kSessionsMayBeSecure && c.transport != nullptr && !c.transport->ready()) return want_write(index, false);
  // 2. Reliable frames, in order; a secure session seals them all at once
  // (a sealed message must go whole): what the socket leaves goes to partial.
  if (kSessionsMayBeSecure && c.transport != nullptr && c.out_head < c.out.size()) {
    c.sealed.clear();
    c.transport->outbound({c.out.data() + c.out_head, c.out.size() - c.out_head}, c.sealed);
    c.out_head = c.out.size();
    long n = write_some(c, c.sealed);
    if (n < 0) return failed();
    if (size_t(n) < c.sealed.size()) {
      c.partial.assign(c.sealed.begin() + n, c.sealed.end());
      c.partial_head = 0;
      c.out.clear();
      c.out_head = 0;
      return want_write(index, true);
    }
  }
  if (c.out_head < c.out.size()) {
    long n = write_some(c, {c.out.data() + c.out_head, c.out.size() - c.out_head});
    if (n < 0) return failed();
    c.out_head += size_t(n);
    if (c.out_head < c.out.size()) return want_write(index, true);
  }
  c.out.clear();
  c.out_head = 0;
  if (c.state == State::Draining) {
    shutdown(c.fd, SHUT_WR);
    return want_write(index, false);
  }
  // 3. The newest data of every device marked dirty for this client.
  while (c.dirty_head < c.dirty.size()) {
    DeviceId dev = c.dirty[c.dirty_head];
    Node::Reader* reader = node_.find_reader(node_.devices_[dev], index);
    uint8_t bits = reader ? reader->dirty : 0;
    for (int slot = 0; slot < Node::kDataSlots && bits != 0; ++slot) {
      if (!(bits & (1u << slot))) continue;
      bits &= uint8_t(~(1u << slot));
      reader->dirty = bits;
      std::span<const uint8_t> frame = node_.devices_[dev].slots[slot].frame;
      if (kSessionsMayBeSecure && c.transport != nullptr) {
        c.sealed.clear();
        c.transport->outbound(frame, c.sealed);
        frame = c.sealed;
      }
      long n = write_some(c, frame);
      if (n < 0) return failed();
      if (size_t(n) < frame.size()) {
        // Keep the tail: a frame once started must be finished.
        c.partial.assign(frame.begin() + n, frame.end());
        c.partial_head = 0;
        if (bits == 0) ++c.dirty_head;
        return want_write(index, true);
      }
    }
    ++c.dirty_head;
  }
  c.dirty.clear();
  c.dirty_head = 0;
  c.partial.clear();
  c.partial_head = 0;
  want_write(index, false);
}

bool Server::refuse_oversized(uint32_t client, std::span<const uint8_t> frame) {
  const wire::Header& h = *wire::trusted_message(frame)->header();
  if (h.kind() == wire::Kind::Data) return true;  // a Pull's data: skipped like pushed data
  char text[96];
  snprintf(text, sizeof text, "the reply has %zu bytes, over the %u bytes of your Hello's max_frame_bytes",
           frame.size(), clients_[client].max_frame);
  wire::MessageWriter w(256);
  auto& b = w.start();
  auto body = wire::CreateError(b, wire::ErrorCode::TooLarge, b.CreateString(text));
  return send_reliable(client, w.finish(wire::make_header(h.addr(), wire::Kind::Nack, h.subtype(), h.seq(),
                                                          node_.now_us()),
                                        wire::Body::Error, body.Union()));
}

bool Server::send_reliable(uint32_t client, std::span<const uint8_t> frame) {
  if (client >= clients_.size() || clients_[client].state == State::Free) return false;
  Client& c = clients_[client];
  if (c.max_frame != 0 && frame.size() > c.max_frame) return refuse_oversized(client, frame);
  size_t queued = c.out.size() - c.out_head;
  if (queued > 0 && queued + frame.size() > node_.options().client_queue_bytes) {
    log_warn("client %u does not read its replies (%zu bytes queued); disconnecting", client, queued);
    close_client(client);
    return false;
  }
  // Stay inside the capacity reserved at accept: compact before growing. Only
  // a single frame larger than the whole queue (a huge device list) grows it.
  if (c.out_head > 0 && c.out.size() + frame.size() > c.out.capacity()) {
    c.out.erase(c.out.begin(), c.out.begin() + long(c.out_head));
    c.out_head = 0;
  }
  c.out.insert(c.out.end(), frame.begin(), frame.end());
  if (!c.writing) flush(client);
  return true;
}

void Server::push_data(uint32_t client, DeviceId device, int slot, std::span<const uint8_t> frame) {
  Client& c = clients_[client];
  if (c.state != State::Open || (c.max_frame != 0 && frame.size() > c.max_frame)) return;
  if (c.udp_port != 0 && frame.size() <= kMaxDatagram) {
    sockaddr_storage to = c.peer;
    if (to.ss_family == AF_INET6) {
      reinterpret_cast<sockaddr_in6*>(&to)->sin6_port = htons(c.udp_port);
    } else {
      reinterpret_cast<sockaddr_in*>(&to)->sin_port = htons(c.udp_port);
    }
    // Latest wins: a datagram the kernel cannot take now is simply dropped.
    (void)!sendto(udp_for(to.ss_family), frame.data(), frame.size(), MSG_DONTWAIT, reinterpret_cast<sockaddr*>(&to),
                  c.peer_len);
    return;
  }
  Node::Reader* reader = node_.find_reader(node_.devices_[device], client);
  if (reader == nullptr) return;
  if (reader->dirty == 0) c.dirty.push_back(device);
  reader->dirty |= uint8_t(1u << slot);
  if (!c.writing) flush(client);
}

void Server::close_with_error(uint32_t client, wire::ErrorCode code, std::string_view text,
                              const wire::Header* about) {
  Client& c = clients_[client];
  if (c.state != State::Open) return;
  wire::MessageWriter w(256);
  auto frame = error_frame(w, about, code, text, node_.now_us());
  // Data and replies not yet sent are dropped: the Error is the last frame.
  c.partial.clear();
  c.partial_head = 0;
  c.dirty.clear();
  c.dirty_head = 0;
  node_.forget_client(client);
  c.out.insert(c.out.end(), frame.begin(), frame.end());
  c.state = State::Draining;
  c.linger = node_.loop().start_timer(kLingerUs, 0, this);
  flush(client);
}

void Server::on_timer(TimerId id) {
  if (id == sweep_) return sweep();
  for (uint32_t i = 0; i < clients_.size(); ++i) {
    if (clients_[i].state == State::Draining && clients_[i].linger == id) {
      clients_[i].linger = 0;
      close_client(i);
    }
  }
}

void Server::close_client(uint32_t index) {
  Client& c = clients_[index];
  if (c.state == State::Free) return;
  if (c.state == State::Open) node_.forget_client(index);
  if (c.linger != 0) node_.loop().cancel_timer(c.linger);
  c.linger = 0;
  node_.loop().unwatch(c.fd);
  if (size_t(c.fd) < client_of_fd_.size()) client_of_fd_[size_t(c.fd)] = 0;
  close(c.fd);
  c.fd = -1;
  c.state = State::Free;
  ++c.generation;
  c.out.clear();
  c.out_head = 0;
  c.partial.clear();
  c.partial_head = 0;
  c.dirty.clear();
  c.dirty_head = 0;
  c.writing = false;
  c.stalled_us = 0;
  c.written = 0;
  c.taken = 0;
  c.udp_port = 0;
  c.max_frame = 0;
  c.transport.reset();
  c.rights.reset();
}

void Server::close_all() {
  for (uint32_t i = 0; i < clients_.size(); ++i) close_client(i);
}

}  // namespace troupe
