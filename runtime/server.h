// Client connections of a node: accept, read frames, write replies and data.
//
// Output to a client has two parts. Reliable frames (Hello, replies, device
// lists, errors) queue in order, up to a byte limit; a client that lets that
// queue overflow is disconnected. Data never queues: a device keeps only its
// newest sample, and a client that cannot take it now is marked "dirty" for
// that device and gets whatever is newest when its socket drains. A slow
// reader therefore loses old samples, never blocks the loop, never grows
// memory.
//
// Slots are bounded (Node::Options::max_clients), so a connection that
// holds one without using it is closed: one that has sent no valid frame
// within hello_timeout_ms of connecting, or one that reads no device and has
// been silent for idle_timeout_ms. A new connection that finds no slot free
// takes the one of a connection already being closed or the oldest that has
// not said anything yet: idle connections never lock a client out.
#pragma once

#include <sys/socket.h>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "runtime/driver.h"
#include "runtime/event_loop.h"
#include "runtime/rights.h"
#include "wire/connection/transport.h"
#include "wire/frame.h"

namespace troupe {

class Node;

class Server final : public FdHandler, public TimerHandler {
 public:
  explicit Server(Node& node);
  ~Server();

  bool start(std::string& error);
  uint16_t port() const { return port_; }
  /// "127.0.0.1:6665", or "127.0.0.1:6665 and [::1]:6665" for localhost.
  std::string listen_text() const;

  bool alive(uint32_t client, uint32_t generation) const;
  uint32_t generation(uint32_t client) const { return clients_[client].generation; }

  /// Queues a reliable frame (copied). False when the client is gone or was
  /// dropped for not reading.
  bool send_reliable(uint32_t client, std::span<const uint8_t> frame);
  /// Offers the newest data of `device` (slot `slot`) to a reader.
  void push_data(uint32_t client, DeviceId device, int slot, std::span<const uint8_t> frame);
  /// Sends an Error frame, then closes the connection gracefully. The
  /// Error echoes the address, subtype and seq of `about`, the offending
  /// message, when there is one.
  void close_with_error(uint32_t client, wire::ErrorCode code, std::string_view text,
                        const wire::Header* about = nullptr);
  void close_all();

  void on_fd(int fd, uint32_t events) override;
  void on_timer(TimerId id) override;

 private:
  enum class State : uint8_t { Free, Open, Draining };
  struct Client {
    int fd = -1;
    uint32_t generation = 0;
    State state = State::Free;
    wire::FrameReader reader{0};
    std::vector<uint8_t> out;  // reliable bytes; [out_head, size) unsent
    size_t out_head = 0;
    std::vector<uint8_t> partial;  // rest of a data frame the socket took part of
    size_t partial_head = 0;
    // Secure sessions: the client's transport (null: plain TCP). Frames are
    // sealed as they go to the socket; sealed bytes the socket did not take
    // wait in `partial` (a sealed message must be sent whole, in order).
    std::unique_ptr<wire::Transport> transport;
    std::shared_ptr<const Rights> rights;  // what it may do (null: everything)
    std::vector<uint8_t> sealed;  // scratch: one batch of sealed bytes
    std::vector<uint8_t> raw;     // scratch: socket bytes for the transport
    std::vector<DeviceId> dirty;  // devices with data not yet sent, FIFO
    size_t dirty_head = 0;
    std::vector<DeviceId> opened;  // devices this client is a reader of
    bool writing = false;  // EPOLLOUT armed
    TimerId linger = 0;
    sockaddr_storage peer{};
    socklen_t peer_len = 0;
    uint16_t udp_port = 0;  // >0: data goes as datagrams to peer:udp_port
    uint32_t max_frame = 0;  // the client's Hello.max_frame_bytes (0: not said)
    uint64_t connected_us = 0;  // event loop clock
    uint64_t heard_us = 0;      // last valid frame; 0: none yet
    // Whether the peer reads: bytes handed to the socket, those of them the
    // peer has acknowledged (last look), and since when it has taken none of
    // what waits for it (event loop clock; 0: nothing waits).
    uint64_t written = 0;
    uint64_t taken = 0;
    uint64_t stalled_us = 0;
  };

  /// One listening socket with its UDP data socket; `localhost` has two.
  struct Listener {
    int tcp = -1;
    int udp = -1;
    int family = 0;
  };

  int listen_on(const sockaddr* addr, socklen_t len, bool v6_only, Listener& out);
  void close_listeners();
  /// The UDP data socket for peers of `family`, -1 when there is none.
  int udp_for(int family) const;
  void accept_clients(int listen_fd);
  void read_client(uint32_t index);
  void flush(uint32_t index);
  /// Writes as much of `bytes` as the socket takes; returns bytes written,
  /// or -1 when the connection failed.
  long write_some(Client& c, std::span<const uint8_t> bytes);
  /// A secure client's bytes: through its transport into its frame reader.
  /// False when the connection was closed (refused or failed).
  bool open_secure(uint32_t index, std::span<const uint8_t> bytes);
  void want_write(uint32_t index, bool on);
  /// Updates `c.stalled_us` from what the peer has acknowledged since the
  /// last look.
  void check_progress(Client& c, uint64_t now);
  void close_client(uint32_t index);
  void handle_hello(uint32_t index, const wire::Message& msg);
  uint32_t index_of_fd(int fd) const;
  /// A slot for a connection from `peer`: a free one, or one taken from a
  /// connection being closed, silent since it connected, or not reading its
  /// data. UINT32_MAX when every slot (or every slot of this address) serves
  /// a client.
  uint32_t slot_for(const sockaddr_storage& peer);
  /// Closes connections past their Hello or idle deadline, and readers
  /// that took no data for the idle deadline.
  void sweep();
  /// How often sweep() runs, us.
  uint64_t sweep_period_us() const;
  /// Says why on a socket about to be closed at once (best effort: a
  /// stalled reader's socket has no room for it).
  void send_error_now(int fd, wire::ErrorCode code, std::string_view text);
  /// A reply too large for the client's announced frame limit becomes a
  /// Nack TooLarge; data that large is not sent to it.
  bool refuse_oversized(uint32_t client, std::span<const uint8_t> frame);

  friend class Node;

  Node& node_;
  Listener listeners_[2];
  int listener_count_ = 0;
  uint16_t port_ = 0;
  TimerId sweep_ = 0;
  std::vector<Client> clients_;
  std::vector<uint32_t> client_of_fd_;  // fd -> client index + 1 (0: none)
};

}  // namespace troupe
