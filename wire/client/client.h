// The C++ client: a connection to a node or simulator, usable blocking
// (connect(), request(), spin_once()) or from the caller's own poll loop
// (poll_fds(), process(), next_timeout_ms()). The connection itself (every
// address of the host tried, Hello, TimeSync, keep-alive, reconnection with
// backoff) is the connection core's (wire/connection); this adds requests,
// devices and proxies. After a reconnection the devices opened before are
// opened again and proxies keep working without the caller rebuilding anything.
#pragma once

#include <poll.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "wire/connection/socket_link.h"
#include "wire/connection/transport.h"
#include "wire/frame.h"
#include "wire/writer.h"

namespace troupe::client {

/// The outcome of a request.
struct Reply {
  enum class Status {
    Ack,           // done; message() is the reply
    Nack,          // refused: code and text say why
    Timeout,       // no reply within the timeout
    Disconnected,  // the connection was lost before the reply came
  };
  Status status = Status::Timeout;
  wire::ErrorCode code = wire::ErrorCode::Unknown;
  std::string text;
  std::vector<uint8_t> frame;  // the reply frame (verified), for Ack and Nack

  bool ok() const { return status == Status::Ack; }
  /// The reply message, or nullptr when there is none.
  const wire::Message* message() const { return frame.empty() ? nullptr : wire::trusted_message(frame); }
};

/// One device as the node lists it.
struct DeviceEntry {
  wire::Address addr;
  std::string robot_name;
  std::string driver;
  /// "r0/position2d:0" (robot name when there is one).
  std::string text() const;
};

class Proxy;

class Client {
 public:
  struct Options {
    /// Sent to the node in Hello; shows in the node's debug log.
    std::string name = "troupe-client";
    wire::Limits limits;
    /// Re-establish a lost connection by itself.
    bool reconnect = true;
    /// Backoff between attempts doubles from min to max, ms.
    uint32_t reconnect_min_ms = 100;
    uint32_t reconnect_max_ms = 2000;
    /// Ask the node to send Data as UDP datagrams (latest wins) instead of TCP.
    bool udp_data = false;
    /// After this long without hearing from the node a TimeSync goes out,
    /// ms (0: no keep-alive); a node that answers nothing within
    /// keepalive_timeout_ms of it is dropped (and reconnected).
    uint32_t keepalive_ms = 2000;
    uint32_t keepalive_timeout_ms = 6000;
    /// Looks up the host: every address it gives is tried, in order.
    wire::Resolver resolver = wire::resolve_system;
    /// Secure sessions: the transport every connection runs through (a
    /// wire/noise NoiseTransport holding our identity and the node's public
    /// key). Null: plain TCP. Data then stays on TCP (udp_data is ignored).
    std::shared_ptr<wire::Transport> transport;
  };

  Client(std::string host, uint16_t port = wire::kDefaultPort);
  Client(std::string host, uint16_t port, Options options);
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  /// Connects and waits for the node's Hello, up to `timeout_ms`. False with
  /// error() when that fails (with reconnect on, later attempts continue in
  /// spin_once()/process()).
  bool connect(int timeout_ms = 5000);
  bool connected() const;
  /// The last problem: resolution, connection, a Nack, an Error from the node.
  const std::string& error() const { return error_; }
  /// The node's name from its Hello.
  const std::string& node_name() const { return link_.connection().peer_name(); }
  /// Node clock minus this process's monotonic clock, us, from TimeSync at
  /// connect (valid once connect() returned true; 0 before). From a
  /// simulator, node time is simulated time. Add it to local time to get node time.
  int64_t clock_offset_us() const { return link_.connection().clock_offset_us(); }
  /// A round trip to the node (TimeSync): when it returns true, everything
  /// sent before it was handled (commands given to their drivers) and any
  /// reply or Nack it caused has arrived. Refreshes clock_offset_us().
  bool sync(int timeout_ms = 2000);
  /// Successful connections so far (1 after the first connect).
  uint32_t connections() const { return link_.connection().connections(); }

  // ---- Devices --------------------------------------------------------------

  /// The node's devices.
  bool device_list(std::vector<DeviceEntry>& out, int timeout_ms = 2000);
  /// Resolves "[ROBOT/]INTERFACE:INDEX"; robot names go through the device list.
  bool resolve(std::string_view spec, wire::Address& out, int timeout_ms = 2000);
  /// Opens a device and waits for the Ack. The device is remembered and
  /// opened again after every reconnect, whether this call succeeded or not.
  /// `compression`: how a camera should pack its images for this client
  /// (one that cannot sends raw rows; each image says how it is packed).
  bool open(const wire::Address& addr, wire::Access access = wire::Access::All,
            wire::Delivery delivery = wire::Delivery::Push,
            wire::ImageCompression compression = wire::ImageCompression::None, int timeout_ms = 2000);
  bool close(const wire::Address& addr, int timeout_ms = 2000);
  /// Asks for the device's latest data; it reaches the handlers and proxies
  /// before this returns true.
  bool pull(const wire::Address& addr, int timeout_ms = 2000);

  // ---- Sending --------------------------------------------------------------

  /// Starts a body: build it in the returned builder, then call command() or
  /// request() with it.
  flatbuffers::FlatBufferBuilder& begin() { return writer_.start(); }
  /// Sends a command (no reply). False when not connected.
  bool command(const wire::Address& addr, uint8_t subtype, wire::Body type = wire::Body::NONE,
               flatbuffers::Offset<void> body = 0);
  /// Sends a request and waits for its Ack or Nack.
  Reply request(const wire::Address& addr, uint8_t subtype, wire::Body type = wire::Body::NONE,
                flatbuffers::Offset<void> body = 0, int timeout_ms = 2000);
  /// Sends a prebuilt frame as it is (tools, tests).
  bool send_frame(std::span<const uint8_t> frame);

  // ---- Receiving ------------------------------------------------------------

  using DataHandler = std::function<void(const wire::Message&)>;
  /// Called for every Data message, after the proxies saw it. Returns an id
  /// for remove_data_handler().
  int add_data_handler(DataHandler handler);
  void remove_data_handler(int id);

  // ---- Running, blocking ----------------------------------------------------

  /// Waits up to `timeout_ms` for traffic and dispatches it (and reconnects
  /// when due). True when some message arrived.
  bool spin_once(int timeout_ms);
  /// Dispatches traffic for `ms` milliseconds.
  void spin_for(int ms);

  // ---- Running from the caller's poll loop ------------------------------------

  /// The descriptors to poll, with their events; returns how many were
  /// written (at most `max`; 2 is always enough: two connection attempts,
  /// or the connection and its UDP socket).
  int poll_fds(pollfd* fds, int max) const;
  /// Handles what poll() reported (the same array), then timers.
  void process(const pollfd* fds, int n);
  /// ms until process() must run even without events (-1: no deadline).
  int next_timeout_ms() const;

 private:
  friend class Proxy;
  struct Opened {
    wire::Address addr;
    wire::Access access;
    wire::Delivery delivery;
    wire::ImageCompression compression;
  };

  wire::LinkState state() const { return link_.connection().state(); }
  /// Takes the connection's events: frames to proxies and handlers, replies
  /// to the call waiting for them.
  void dispatch_events();
  void on_up();
  void on_down(std::string_view why);
  void on_frame(std::span<const uint8_t> frame, const wire::Message& msg);
  void open_udp();
  void read_udp();
  bool queue(std::span<const uint8_t> frame);
  uint32_t next_seq() { return link_.connection().next_seq(); }
  Reply wait_reply(uint32_t seq, int timeout_ms);
  bool send_simple(const wire::Address& addr, wire::Kind kind, uint32_t seq, wire::Body type = wire::Body::NONE,
                   flatbuffers::Offset<void> body = 0);
  void add_proxy(Proxy* proxy);
  void remove_proxy(Proxy* proxy);

  std::string host_;
  Options options_;
  wire::SocketLink link_;
  int udp_fd_ = -1;
  std::string error_;
  wire::MessageWriter writer_;
  wire::MessageWriter control_writer_;  // session messages while writer_ holds a body
  std::vector<Opened> opened_;
  std::vector<Proxy*> proxies_;
  std::vector<std::pair<int, DataHandler>> handlers_;
  int next_handler_id_ = 1;
  // The reply a blocking call waits for, if any.
  uint32_t awaited_seq_ = 0;
  bool awaited_done_ = false;
  Reply awaited_;
};

}  // namespace troupe::client
