// The connection core: one connection to a node as a state machine that does
// no I/O. Bytes from the socket go in; frames and events come out; the bytes
// to send, what to do with sockets (resolve, connect, abandon, close) and the
// next deadline come out as values. It never reads a clock: every call that
// can change something takes `now_us`, the caller's monotonic clock in
// microseconds. So it is tested byte by byte, and it is the one place for
// the session protocol: Hello, TimeSync, framing and verification of inbound
// frames, keep-alive, attempts at every address (RFC 8305's staggered
// attempts), reconnect backoff, and the seam for an authenticated transport.
//
// States (wire/README.md, "Connection lifecycle"; the Python client uses the
// same names):
//   Idle       not started, stopped, or failed with reconnection off
//   Waiting    backing off before the next attempt
//   Connecting resolving the host, opening the transport to each address
//   Handshake  transport open: its own handshake (none for plain TCP), our
//              Hello sent, the peer's awaited
//   Up         the peer's Hello arrived: frames flow
//
// The adapters (socket_link.h for blocking and poll loops; the node's event
// loop in drivers/passthrough) move bytes and report what sockets did.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "wire/frame.h"
#include "wire/writer.h"

namespace troupe::wire {

class Transport;

/// next_deadline_us() when nothing is due.
inline constexpr uint64_t kNoDeadline = UINT64_MAX;

/// Transport attempts open at once while connecting (RFC 8305 starts the
/// next address while earlier ones are still trying). With the data socket,
/// a caller's poll set never needs more than 2 entries for a connection.
inline constexpr uint32_t kMaxAttemptsInFlight = 2;

enum class LinkState : uint8_t { Idle, Waiting, Connecting, Handshake, Up };

/// "idle", "waiting", "connecting", "handshake", "up".
const char* link_state_name(LinkState s);

struct ConnectionOptions {
  /// Our name, sent in Hello (shows in the peer's log).
  std::string name = "troupe-client";
  /// "HOST:PORT" as the user named the peer, for messages.
  std::string target;
  /// How messages name the peer: "the node" gives "the node closed the
  /// connection", "remote 10.0.0.7:6665" gives "remote 10.0.0.7:6665 ...".
  std::string peer = "the node";
  Limits limits;
  /// Connect again after a failure or a lost connection.
  bool reconnect = true;
  /// Wait before the next attempt: doubles from min to max while attempts
  /// fail, back to min once a connection came up, us.
  uint64_t backoff_min_us = 100'000;
  uint64_t backoff_max_us = 2'000'000;
  /// RFC 8305's Connection Attempt Delay: the next address is tried when
  /// the current one has neither failed nor connected after this long, us.
  uint64_t attempt_delay_us = 250'000;
  /// Resolving, connecting and the handshake together, us (0: no limit).
  uint64_t connect_timeout_us = 10'000'000;
  /// While up, a TimeSync goes out after this long without receiving
  /// anything, us (0: no keep-alive) ...
  uint64_t keepalive_us = 0;
  /// ... and the connection is dropped when nothing arrives within this
  /// long of that TimeSync going out, us.
  uint64_t keepalive_timeout_us = 0;
  /// Bytes waiting to be sent, at most (0: no limit). A peer that does not
  /// read beyond it is dropped rather than let the queue grow.
  size_t max_output_bytes = 0;
  /// Our UDP port for Data datagrams, sent in Hello (0: data over TCP).
  uint16_t udp_port = 0;
  /// Send a TimeSync with Hello, so that clock_offset_us() is known soon
  /// after the connection is up.
  bool sync_clock = true;
};

/// What the adapter must do with sockets.
enum class ActionKind : uint8_t {
  None,
  Resolve,  // look up the target's addresses: answer resolved() or resolve_failed()
  Connect,  // open a transport to `candidate`: answer attempt_connected() or attempt_failed()
  Abandon,  // close the attempt to `candidate` (another one won, or time ran out)
  Close,    // close the established transport
};

struct Action {
  ActionKind kind = ActionKind::None;
  uint32_t candidate = 0;
};

enum class EventKind : uint8_t {
  None,
  Up,      // the peer's Hello arrived; `frame` and `message` are that Hello
  Down,    // an attempt failed or the connection ended; `text` says why
  Synced,  // a TimeSync this side asked for came back; clock_offset_us() is fresh
  Frame,   // a verified frame from the peer
};

/// An event. `frame` (prefix included), `message` (verified) and `text`
/// stay valid until the next call to read_space(), received() or
/// next_event().
struct Event {
  EventKind kind = EventKind::None;
  std::span<const uint8_t> frame;
  const Message* message = nullptr;
  std::string_view text;
};

class Connection {
 public:
  /// `transport` (not owned; nullptr: plain bytes) sits between frames and
  /// the socket: see transport.h.
  explicit Connection(ConnectionOptions options, Transport* transport = nullptr);
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;
  ~Connection();

  // ---- Driven by the adapter --------------------------------------------------

  /// From Idle or Waiting: the first (or next) attempt begins now.
  void start(uint64_t now_us);
  /// Ends the connection without an event and without reconnecting.
  void stop();
  /// The target's addresses in the order to try them (resolver.h orders them
  /// as RFC 8305 asks); the texts name them in messages.
  void resolved(uint64_t now_us, std::vector<std::string> candidates);
  void resolve_failed(uint64_t now_us, std::string why);
  void attempt_connected(uint64_t now_us, uint32_t candidate);
  /// `why`: what the socket said ("Connection refused").
  void attempt_failed(uint64_t now_us, uint32_t candidate, std::string_view why);
  /// Where the next bytes from the socket go (at least `min_bytes`).
  std::span<uint8_t> read_space(size_t min_bytes = 16 * 1024);
  /// `n` bytes were written into read_space().
  void received(uint64_t now_us, size_t n);
  /// The established transport ended: `why` empty for an orderly end of
  /// stream, else what the socket said. Frames received before it are
  /// still delivered, then Down.
  void transport_closed(uint64_t now_us, std::string_view why);
  /// Acts on deadlines that are due (call it when next_deadline_us() passed).
  void tick(uint64_t now_us);

  /// Bytes to write to the established transport.
  std::span<const uint8_t> output() const;
  /// `n` bytes of output() were written.
  void consumed(size_t n);
  /// The next socket action, or None.
  Action next_action();
  /// When tick() must run next (monotonic us), or kNoDeadline.
  uint64_t next_deadline_us() const;

  // ---- Used by the owner --------------------------------------------------------

  /// The next event, or kind None when there is none now.
  Event next_event();
  /// Queues a whole frame. While connecting, frames wait and go out after
  /// the Hello. False when not connecting or up, or when the peer does not
  /// read (the connection is then dropped).
  bool send(std::span<const uint8_t> frame);
  /// Drops the connection (or the attempt) for `why`, with a Down event;
  /// reconnects after the backoff when that is on.
  void close(uint64_t now_us, std::string why);
  /// Sends a TimeSync now; its reply gives an Event::Synced carrying it.
  /// Returns its sequence number, 0 when not up.
  uint32_t request_time_sync(uint64_t now_us);
  /// A sequence number for a message on this connection.
  uint32_t next_seq();

  LinkState state() const { return state_; }
  bool up() const { return state_ == LinkState::Up; }
  /// The caller's clock (us) when the state last changed.
  uint64_t since_us() const { return since_us_; }
  /// Why the last attempt or connection ended.
  const std::string& error() const { return error_; }
  /// The peer's name from its Hello.
  const std::string& peer_name() const { return peer_name_; }
  /// Peer clock minus the caller's clock, us, from the last TimeSync.
  int64_t clock_offset_us() const { return clock_offset_us_; }
  /// A TimeSync has come back on this connection.
  bool clock_synced() const { return clock_synced_; }
  /// Connections that came up so far.
  uint32_t connections() const { return connections_; }
  const ConnectionOptions& options() const { return options_; }
  /// Changes the UDP port the next Hello announces.
  void set_udp_port(uint16_t port) { options_.udp_port = port; }

 private:
  enum class Attempt : uint8_t { NotStarted, InFlight, Failed };
  struct Candidate {
    std::string name;
    Attempt attempt = Attempt::NotStarted;
    std::string why;
  };

  void set_state(LinkState s, uint64_t now_us);
  void begin_attempt(uint64_t now_us);
  bool start_next_candidate(uint64_t now_us);
  void fail_attempt(uint64_t now_us, const std::string& why);
  std::string connect_error() const;
  void reset_session();
  void transport_up(uint64_t now_us);
  void send_prologue(uint64_t now_us);
  /// Ends an established transport (a Close action) for `why`.
  void drop(uint64_t now_us, const std::string& why);
  /// Reports Down and goes to Waiting (or Idle).
  void end(uint64_t now_us, const std::string& why);
  bool transport_ready() const;
  void queue_bytes(std::span<const uint8_t> bytes);
  /// Passes what waits in out_ through the transport, once it is ready.
  void seal_pending();
  /// Handles one frame from the peer: true when it is an event for the owner.
  bool on_frame(std::span<const uint8_t> frame, Event& out);

  ConnectionOptions options_;
  Transport* transport_;
  LinkState state_ = LinkState::Idle;
  bool running_ = false;
  uint64_t since_us_ = 0;
  uint64_t now_us_ = 0;  // the latest time any call gave, for what calls without one start
  std::string error_;

  // Connecting
  bool resolving_ = false;
  std::vector<Candidate> candidates_;
  uint32_t in_flight_ = 0;
  uint64_t stagger_at_us_ = kNoDeadline;  // the next candidate starts
  uint64_t attempt_deadline_us_ = kNoDeadline;
  uint64_t retry_at_us_ = kNoDeadline;  // Waiting: the next attempt
  uint64_t backoff_us_ = 0;

  // Established
  FrameReader reader_;
  MessageWriter writer_;
  std::vector<uint8_t> out_;  // frames to send; [out_head_, size) unsent
  size_t out_head_ = 0;
  std::vector<uint8_t> wire_out_;  // out_ as the transport sealed it (with a transport)
  size_t wire_head_ = 0;
  std::vector<uint8_t> raw_in_;  // socket bytes for the transport to open
  bool hello_sent_ = false;
  bool closing_ = false;  // the transport ended; frames before it still to deliver
  uint64_t closed_at_us_ = 0;
  std::string close_why_;
  uint64_t last_rx_us_ = 0;
  bool ping_outstanding_ = false;
  uint32_t ping_seq_ = 0;  // the last keep-alive TimeSync
  uint64_t ping_sent_us_ = 0;
  uint32_t sync_seq_ = 0;  // the TimeSync whose reply gives Synced
  uint32_t seq_ = 0;
  std::string peer_name_;
  int64_t clock_offset_us_ = 0;
  bool clock_synced_ = false;
  uint32_t connections_ = 0;

  std::vector<Action> actions_;
  size_t action_head_ = 0;
  std::vector<std::string> downs_;  // Down events not yet taken, oldest first
  size_t down_head_ = 0;
  std::string event_text_;  // the text of the Down event last returned
};

}  // namespace troupe::wire
