// A connection to a remote node that lives inside the local node's event
// loop: non-blocking connect, Hello, a keep-alive, reconnection with
// backoff. It never blocks the loop: the address is numeric (no DNS), the
// connect and the handshake have deadlines, and writes only queue.
//
// States: Waiting (for the next attempt) -> Connecting (TCP) -> Handshake
// (our Hello sent, waiting for the remote's) -> Up. Any failure closes the
// socket and goes back to Waiting with the next backoff.
#pragma once

#include <netinet/in.h>
#include <sys/socket.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "runtime/event_loop.h"
#include "wire/frame.h"
#include "wire/writer.h"

namespace troupe::drivers::passthrough {

enum class LinkState : uint8_t { Waiting, Connecting, Handshake, Up };

/// "waiting", "connecting", "handshake", "up".
const char* link_state_name(LinkState s);

/// What the link tells its owner. Called from the loop, never re-entrantly
/// from RemoteLink's public methods except close().
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
  uint64_t idle_timeout_us = 4'000'000;
  /// Frames queued for a remote that does not read, bytes: beyond it the
  /// link is dropped (and rebuilt) rather than grown.
  size_t max_queue_bytes = 4u << 20;
  wire::Limits limits;
};

class RemoteLink final : public FdHandler, public TimerHandler {
 public:
  RemoteLink(EventLoop& loop, LinkListener& listener);
  ~RemoteLink();
  RemoteLink(const RemoteLink&) = delete;
  RemoteLink& operator=(const RemoteLink&) = delete;

  /// Parses the address (false with `error` when it is not numeric) and
  /// starts the first attempt at once.
  bool start(const LinkOptions& options, std::string& error);
  /// Closes the socket and stops retrying.
  void stop();

  LinkState state() const { return state_; }
  bool up() const { return state_ == LinkState::Up; }
  /// Nothing waits in the outbound queue.
  bool idle() const { return out_head_ == out_.size(); }
  /// Loop time (us) of the last state change.
  uint64_t since_us() const { return since_us_; }
  const std::string& last_error() const { return last_error_; }
  /// Successful handshakes so far.
  uint32_t connections() const { return connections_; }
  /// "127.0.0.1:6665".
  const std::string& remote_text() const { return remote_text_; }

  /// Queues a frame for the remote (only while up). False when the link is
  /// not up or the queue overflowed (then the link is closed).
  bool send(std::span<const uint8_t> frame);
  /// A sequence number for a request or control message on this link.
  uint32_t next_seq() { return ++seq_; }
  /// Drops the connection for `why` and reconnects after the backoff.
  void close(const std::string& why);

  void on_fd(int fd, uint32_t events) override;
  void on_timer(TimerId id) override;

 private:
  void attempt();
  void on_connected();
  void read_some();
  void flush();
  void dispatch(std::span<const uint8_t> frame);
  void set_state(LinkState s);
  void arm(TimerId& timer, uint64_t delay_us, uint64_t period_us = 0);
  void disarm(TimerId& timer);

  EventLoop& loop_;
  LinkListener& listener_;
  LinkOptions options_;
  sockaddr_storage addr_{};
  socklen_t addr_len_ = 0;
  std::string remote_text_;
  LinkState state_ = LinkState::Waiting;
  bool running_ = false;
  int fd_ = -1;
  uint32_t events_ = 0;     // watched on fd_
  TimerId step_timer_ = 0;  // next attempt, or the connect/handshake deadline
  TimerId ping_timer_ = 0;
  uint64_t backoff_us_ = 0;
  uint64_t since_us_ = 0;
  uint64_t last_rx_us_ = 0;
  uint32_t seq_ = 0;
  uint32_t connections_ = 0;
  std::string last_error_;
  wire::FrameReader reader_;
  wire::MessageWriter writer_;
  std::vector<uint8_t> out_;
  size_t out_head_ = 0;
};

}  // namespace troupe::drivers::passthrough
