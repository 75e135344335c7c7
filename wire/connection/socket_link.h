// The connection core over real TCP sockets, driven by poll(): the adapter
// for blocking programs and for callers with their own poll loop (the
// client library, the recorder, the test clients; the node's event loop
// drives it through drivers/passthrough/remote_link.h). It carries out the
// core's actions (resolving with the injected resolver, non-blocking connect
// attempts, closing), moves bytes both ways and ticks the core's deadlines.
// The owner takes events with next_event().
#pragma once

#include <poll.h>

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "wire/connection/connection.h"
#include "wire/connection/resolver.h"

namespace troupe::wire {

class SocketLink {
 public:
  /// `transport`: see Connection (nullptr: plain bytes).
  SocketLink(std::string host, uint16_t port, ConnectionOptions options, Resolver resolver = resolve_system,
             Transport* transport = nullptr);
  ~SocketLink();
  SocketLink(const SocketLink&) = delete;
  SocketLink& operator=(const SocketLink&) = delete;

  Connection& connection() { return conn_; }
  const Connection& connection() const { return conn_; }
  const std::string& host() const { return host_; }
  uint16_t port() const { return port_; }

  /// Begins an attempt now (from Idle, or cuts a Waiting short).
  void start();
  /// Closes every socket; no event, no reconnect.
  void stop();
  /// start(), then waits up to `timeout_ms` for the transport only (the
  /// Handshake state), not for the peer's Hello: for a caller that runs the
  /// node in its own thread. False with `error` when the attempt failed.
  bool open_transport(int timeout_ms, std::string& error);

  /// The descriptors to poll, with their events; returns how many were
  /// written (at most `max`; kMaxAttemptsInFlight is always enough).
  int poll_fds(pollfd* fds, int max) const;
  /// Handles what poll() reported (entries of other descriptors are
  /// skipped), then the deadlines that are due.
  void process(const pollfd* fds, int n);
  /// ms until process() must run even without events (-1: no deadline).
  int next_timeout_ms() const;
  /// Polls this link alone for up to `timeout_ms` (-1: no limit, but never
  /// past a deadline) and processes what happened.
  void wait(int timeout_ms);

  /// The connection's next event (Connection::next_event), after which
  /// what it led to is carried out (a bad frame closes the socket).
  Event next_event();
  /// Queues a frame and writes what the socket takes now.
  bool send(std::span<const uint8_t> frame);
  /// Sends a TimeSync (Connection::request_time_sync); its seq, 0 when not up.
  uint32_t request_time_sync();
  /// Drops the connection for `why` (a Down event; reconnects after the backoff).
  void close(std::string why);
  /// The established socket, -1 while there is none.
  int fd() const { return fd_; }
  /// Called with each socket just before it is closed: an event loop that
  /// watches it must forget it first (a closed number is soon reused).
  void on_close(std::function<void(int fd)> hook) { close_hook_ = std::move(hook); }

 private:
  struct Attempt {
    uint32_t candidate;
    int fd;
  };

  /// Carries out the core's actions until there are none, then writes.
  void perform();
  void connect_candidate(uint32_t candidate);
  void attempt_done(size_t index, int error);
  void close_attempt(uint32_t candidate);
  void close_fd();
  void release(int fd);
  void flush();
  void read();

  std::string host_;
  uint16_t port_;
  Resolver resolver_;
  Connection conn_;
  std::vector<Endpoint> endpoints_;
  std::vector<Attempt> attempts_;
  int fd_ = -1;
  std::function<void(int)> close_hook_;
};

}  // namespace troupe::wire
