// The node: one event loop, the device registry, the TCP/UDP server and the
// router between clients and drivers. Drivers see it through the methods
// under "For drivers"; troupe-node and troupe-sim build one with Node::Options.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "runtime/driver.h"
#include "runtime/event_loop.h"
#include "runtime/rights.h"
#include "wire/connection/transport.h"
#include "wire/frame.h"
#include "wire/writer.h"

namespace troupe {

class Server;

/// Whether this build's nodes may run secure sessions and client rights
/// (Options::make_transport, rights_of). False in a board built without
/// them (TROUPE_PLAIN_ONLY): the compiler then drops the code, which the
/// armhf core's 64 KiB budget needs.
#ifdef TROUPE_PLAIN_ONLY
inline constexpr bool kSessionsMayBeSecure = false;
#else
inline constexpr bool kSessionsMayBeSecure = true;
#endif

class Node final : public TimerHandler {
 public:
  struct Options {
    std::string name = "troupe-node";
    /// Listen address and TCP port; the UDP data socket uses the same port.
    /// "localhost" is both loopbacks, 127.0.0.1 and ::1; an address (IPv6
    /// with or without brackets, "0.0.0.0", "::") is that address alone.
    std::string listen = "localhost";
    uint16_t port = wire::kDefaultPort;
    bool udp = true;
    /// Clients served at once. One more takes the slot of a connection that
    /// has sent nothing yet (or is being closed), or is told so and closed.
    uint16_t max_clients = 64;
    /// Clients served at once from one IP address (0: up to max_clients).
    /// Keeps one host from taking every slot on a node serving a network.
    uint16_t max_clients_per_address = 0;
    /// A connection that has sent no valid frame (its Hello, normally) this
    /// long after connecting is closed, ms (0: never).
    uint32_t hello_timeout_ms = 5000;
    /// A connection that reads no device and has sent nothing for this long
    /// is closed, ms (0: never); so is a reader whose socket has taken no
    /// data for this long (it stopped reading).
    uint32_t idle_timeout_ms = 60000;
    /// Replies and other reliable frames queued for a client that is not
    /// reading, bytes. A client over it is disconnected. Data never queues:
    /// a slow reader gets the newest sample when it catches up.
    uint32_t client_queue_bytes = 64 * 1024;
    /// Kernel send buffer per client socket, bytes (0: the kernel's default,
    /// which grows to megabytes). Bounds what a client that stops reading
    /// can pin in the kernel.
    uint32_t socket_send_bytes = 0;
    wire::Limits limits;
    /// A request without a reply by then is answered Timeout, ms.
    uint32_t request_timeout_ms = 2000;
    /// Requests waiting for drivers at once.
    uint32_t max_pending_requests = 256;
    size_t max_timers = 256;
    /// Secure sessions: makes the transport of each new connection (a
    /// wire/noise NoiseTransport; its handshake runs before any frame, and
    /// data stays on TCP). Unset: plain TCP.
    std::function<std::unique_ptr<wire::Transport>()> make_transport;
    /// Secure sessions: the rights of the client that proved `peer` (its
    /// transport's peer_identity()). Unset, or null for a peer: every right.
    std::function<std::shared_ptr<const Rights>(const std::string& peer)> rights_of;
  };

  explicit Node(Options options);
  ~Node();
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;

  // ---- Building and running -------------------------------------------------

  /// Registers a device; fails (kNoDevice) on a duplicate address.
  /// `robot_name` is what `troupe ls` shows before the interface ("r0").
  DeviceId add_device(const wire::Address& addr, Driver* driver, std::string_view driver_name,
                      std::string_view robot_name = {});
  /// Takes ownership of a driver and calls its setup(); false with `error`
  /// and, when given, `failure` saying whether its hardware is missing.
  bool add_driver(std::unique_ptr<Driver> driver, const DriverSetup& setup, std::string& error,
                  SetupFailure* failure = nullptr);
  /// Opens the listening sockets. False with `error` (e.g. port in use).
  bool start(std::string& error);
  /// Runs until stop() (or a signal handler calling it).
  void run();
  /// One loop iteration, waiting at most `max_wait_us` (for embedding the
  /// node in another loop, e.g. the simulator's).
  void poll(int64_t max_wait_us);
  void stop() { loop_.stop(); }
  /// Calls every driver's shutdown() in reverse order and closes clients.
  void shutdown();

  /// The bound TCP port (useful with port 0 in tests).
  uint16_t port() const;
  /// What it listens on: "127.0.0.1:6665 and [::1]:6665" for localhost.
  std::string listen_text() const;
  const Options& options() const { return options_; }

  // ---- For drivers ----------------------------------------------------------

  EventLoop& loop() { return loop_; }
  /// The node's clock, us. Timestamps of published data default to it.
  uint64_t now_us() const;
  /// Replaces the clock (troupe-sim publishes in simulated time).
  void set_clock(uint64_t (*clock_us)(void* ctx), void* ctx);

  DeviceId find_device(const wire::Address& addr) const;
  const wire::Address& address(DeviceId device) const;
  size_t device_count() const { return devices_.size(); }
  /// True while some client (or a driver) reads the device's data: a driver
  /// may skip computing data nobody reads.
  bool has_readers(DeviceId device) const;
  /// True while some client reads the device asking for images packed as
  /// `compression` (its Open's), or, for None, while a driver reads it.
  bool has_readers(DeviceId device, wire::ImageCompression compression) const;
  /// Drops the device's stored samples (a new reader gets nothing until the
  /// next publish): for a driver whose stored data went stale while nobody
  /// read the device.
  void forget_data(DeviceId device);

  /// Delivers `source`'s data to `driver->on_data()` (a driver's "requires").
  void subscribe(DeviceId source, Driver* driver);

  /// Starts a message: clears the node's writer and returns its builder for
  /// the body. Follow with publish(), ack() or nack-free replies.
  flatbuffers::FlatBufferBuilder& begin() { return writer_.start(); }

  /// Publishes Data for `device` with the body built since begin(). `time_us`
  /// 0 means now. Readers get it pushed (or on Pull); drivers subscribed to
  /// the device get on_data().
  void publish(DeviceId device, uint8_t subtype, wire::Body type, flatbuffers::Offset<void> body,
               uint64_t time_us = 0) {
    publish_at(device, subtype, type, body, time_us ? time_us : now_us());
  }
  /// publish() with the header time exactly `time_us`, 0 included: a replay
  /// gives back a sample a simulator took at time 0 as it was sent.
  void publish_at(DeviceId device, uint8_t subtype, wire::Body type, flatbuffers::Offset<void> body,
                  uint64_t time_us);
  /// Publishes like publish(), but only to the readers whose Open asked for
  /// `compression` (and, for None, to the drivers subscribed): a camera
  /// packs each image once per compression its readers asked for. A device
  /// that compresses nothing uses publish(), and every reader gets raw rows.
  void publish_packed(DeviceId device, wire::ImageCompression compression, uint8_t subtype, wire::Body type,
                      flatbuffers::Offset<void> body);

  /// Sends a request with the body built since begin() to another driver's
  /// `device` on behalf of `from` (a driver's "requires", e.g. mcl asking the
  /// map for its tiles). Exactly one reply comes back through
  /// from->on_reply(): the target's Ack or Nack, or a Nack Timeout. It may
  /// come before this returns. False when no request slot is free or the
  /// device has no driver (then no reply comes).
  bool request(DeviceId device, uint8_t subtype, uint32_t seq, wire::Body type,
               flatbuffers::Offset<void> body, Driver* from);

  /// Sends a command with the body built since begin() to another driver's
  /// `device` (a bridge passing on velocities from another ecosystem). It is
  /// delivered like a client's: at the end of the loop iteration, the newest
  /// for the device replacing any still waiting.
  void command(DeviceId device, uint8_t subtype, wire::Body type, flatbuffers::Offset<void> body);

  /// Replies Ack with the body built since begin() (or none).
  void ack(RequestToken token, wire::Body type = wire::Body::NONE,
           flatbuffers::Offset<void> body = 0);
  /// Replies Nack with a reason.
  void nack(RequestToken token, wire::ErrorCode code, std::string_view why);
  /// The request's device, or kNoDevice when the token is no longer valid.
  DeviceId request_device(RequestToken token) const;

  // ---- For the server (runtime internals) -----------------------------------

  void on_timer(TimerId id) override;

 private:
  friend class Server;

  static constexpr int kDataSlots = 4;  // data subtypes remembered per device

  static constexpr uint8_t kEveryReader = 0xff;  // DataSlot::compression of publish()'s data

  struct DataSlot {
    uint8_t subtype = 0;
    uint8_t compression = kEveryReader;  // or the wire::ImageCompression its readers asked for
    std::vector<uint8_t> frame;          // newest Data frame of this subtype
  };
  struct Reader {
    uint32_t client;    // server client slot
    uint8_t delivery;   // wire::Delivery
    uint8_t dirty = 0;  // bit i: slot i not yet sent to this client
    uint8_t access = uint8_t(wire::Access::All);
    uint8_t compression = 0;  // wire::ImageCompression asked in the Open
    bool wants(const DataSlot& slot) const {
      return slot.compression == kEveryReader || slot.compression == compression;
    }
  };
  struct Device {
    wire::Address addr;
    Driver* driver = nullptr;
    std::string driver_name;
    std::string robot_name;
    uint32_t seq = 0;
    DataSlot slots[kDataSlots];
    std::vector<Reader> readers;
    std::vector<Driver*> subscribers;
    std::vector<uint8_t> command;  // newest command frame, waiting for delivery
    bool command_pending = false;
  };
  struct Pending {
    bool active = false;
    uint32_t generation = 0;
    uint32_t client = 0;
    uint32_t client_generation = 0;
    DeviceId device = kNoDevice;
    Driver* requester = nullptr;  // a driver's request (Node::request), not a client's
    uint8_t subtype = 0;
    uint32_t seq = 0;
    uint64_t deadline_us = 0;
  };

  // Router: called by the server for each verified frame from a client.
  void route(uint32_t client, const wire::Message& msg, std::span<const uint8_t> frame);
  void handle_command(uint32_t client, DeviceId dev, const wire::Message& msg,
                      std::span<const uint8_t> frame);
  void handle_request(uint32_t client, DeviceId dev, const wire::Message& msg);
  void handle_open(uint32_t client, DeviceId dev, const wire::Message& msg);
  void handle_close(uint32_t client, DeviceId dev, const wire::Message& msg);
  void handle_pull(uint32_t client, DeviceId dev, const wire::Message& msg);
  /// Whether the client holds `right` (or `or_else`) on the device; if not,
  /// answers the message Nack Forbidden.
  bool permitted(uint32_t client, DeviceId dev, const wire::Message& msg, Right right) {
    return permitted(client, dev, msg, right, right);
  }
  bool permitted(uint32_t client, DeviceId dev, const wire::Message& msg, Right right, Right or_else);
  void send_device_list(uint32_t client, const wire::Message& msg);
  void send_time_sync(uint32_t client, const wire::Message& msg);
  void send_hello(uint32_t client);
  /// Reply without a body or with an Error body (Ack/Nack/Error kinds).
  void reply_status(uint32_t client, const wire::Header& to, wire::Kind kind,
                    wire::ErrorCode code = wire::ErrorCode::Unknown, std::string_view text = {});
  void deliver_commands();
  void forget_client(uint32_t client);
  void arm_request_timer();
  bool claim_request_slot(uint32_t& slot);
  void reply_to_driver(Pending& p, std::span<const uint8_t> frame);
  Reader* find_reader(Device& dev, uint32_t client);
  int slot_for(Device& dev, uint8_t subtype, uint8_t compression);
  void publish_to(DeviceId device, uint8_t compression, uint8_t subtype, wire::Body type,
                  flatbuffers::Offset<void> body, uint64_t time_us);

  Options options_;
  EventLoop loop_;
  std::unique_ptr<Server> server_;
  wire::MessageWriter writer_;
  wire::MessageWriter reply_writer_;  // replies built while writer_ holds a body
  std::vector<Device> devices_;
  std::unordered_map<uint64_t, DeviceId> by_address_;
  std::vector<std::unique_ptr<Driver>> drivers_;
  std::vector<DeviceId> pending_commands_;
  std::vector<Pending> pending_;
  TimerId request_timer_ = 0;
  uint64_t request_timer_deadline_ = 0;
  uint64_t (*clock_)(void*) = nullptr;
  void* clock_ctx_ = nullptr;
  bool shut_down_ = false;
};

}  // namespace troupe
