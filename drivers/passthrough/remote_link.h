// The connection core (wire/connection) inside a node's event loop: the
// adapter that watches the link's sockets and its next deadline with the
// loop's epoll and timers, and hands the events to a listener. The session
// itself (every address tried, Hello, keep-alive, reconnection with backoff,
// verification) is the core's. It never blocks the loop: the host must be
// numeric or `localhost` (no DNS), the connect and the handshake have
// deadlines, and writes only queue.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "runtime/event_loop.h"
#include "wire/connection/socket_link.h"

namespace troupe::drivers::passthrough {

/// What the link tells its owner, from the loop.
class LinkListener {
 public:
  /// The remote's Hello arrived: frames may be sent.
  virtual void on_link_up() = 0;
  /// The connection is gone (or an attempt failed) for `why`.
  virtual void on_link_down(const std::string& why) = 0;
  /// A verified frame from the remote (not Hello or the keep-alive reply).
  virtual void on_remote_frame(const wire::Message& msg) = 0;
  /// The outbound queue emptied: held-back frames may go now.
  virtual void on_link_writable() = 0;

 protected:
  ~LinkListener() = default;
};

struct LinkOptions {
  std::string host;  // numeric, or "localhost"
  uint16_t port = 0;
  std::string client_name = "passthrough";  // sent in Hello
  uint64_t backoff_min_us = 100'000;
  uint64_t backoff_max_us = 5'000'000;
  uint64_t connect_timeout_us = 3'000'000;
  /// A keep-alive goes out after a quarter of it without traffic; a remote
  /// that sends nothing at all for this long is dropped, us.
  uint64_t idle_timeout_us = 4'000'000;
  /// Frames queued for a remote that does not read, bytes: beyond it the
  /// link is dropped (and rebuilt) rather than grown.
  size_t max_queue_bytes = 4u << 20;
  wire::Limits limits;
  /// A secure session's transport (wire/noise/client_keys.h) under every
  /// connection; nullptr: plain TCP.
  std::shared_ptr<wire::Transport> transport;
};

class RemoteLink final : public FdHandler, public TimerHandler {
 public:
  RemoteLink(EventLoop& loop, LinkListener& listener);
  ~RemoteLink();
  RemoteLink(const RemoteLink&) = delete;
  RemoteLink& operator=(const RemoteLink&) = delete;

  /// Checks the address (false with `error` when it is a name that would
  /// need DNS) and starts the first attempt at once.
  bool start(const LinkOptions& options, std::string& error);
  /// Closes the sockets and stops retrying.
  void stop();

  wire::LinkState state() const { return conn().state(); }
  bool up() const { return conn().up(); }
  /// Nothing waits in the outbound queue.
  bool idle() const { return conn().output().empty(); }
  /// Loop time (us) of the last state change.
  uint64_t since_us() const { return conn().since_us(); }
  const std::string& last_error() const { return conn().error(); }
  /// Successful handshakes so far.
  uint32_t connections() const { return conn().connections(); }
  /// "127.0.0.1:6665", "localhost:6665", "[::1]:6665".
  const std::string& remote_text() const { return remote_text_; }

  /// Queues a frame for the remote (only while up). False when the link is
  /// not up or the queue overflowed (then the link is closed).
  bool send(std::span<const uint8_t> frame);
  /// A sequence number for a request or control message on this link.
  uint32_t next_seq() { return link_->connection().next_seq(); }
  /// Drops the connection for `why` and reconnects after the backoff.
  void close(const std::string& why);

  void on_fd(int fd, uint32_t events) override;
  void on_timer(TimerId id) override;

 private:
  const wire::Connection& conn() const { return link_->connection(); }
  /// Hands events to the listener, then follows the link's descriptors and
  /// deadline with the loop's watches and timer.
  void service();
  /// Stops watching a socket the link is about to close.
  void forget(int fd);
  void sync_watches();
  void arm_timer();

  EventLoop& loop_;
  LinkListener& listener_;
  std::shared_ptr<wire::Transport> transport_;  // the link's, kept as long as it
  std::unique_ptr<wire::SocketLink> link_;
  std::string remote_text_;
  pollfd watched_[wire::kMaxAttemptsInFlight]{};
  int watched_count_ = 0;
  TimerId timer_ = 0;
  uint64_t timer_at_us_ = wire::kNoDeadline;
  bool servicing_ = false;
  bool again_ = false;  // service() was asked for while it ran
  bool busy_ = false;   // frames were waiting to be written
};

}  // namespace troupe::drivers::passthrough
