// Test fixtures: a real Node on a loopback port, run in a thread of its own
// (the node is single-threaded; tests talk to it only through sockets and
// the atomics of the test driver), raw TCP connections for sending bad bytes,
// and a recorder driver whose behaviour tests can steer.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "runtime/node.h"
#include "wire/client/client.h"
#include "wire/frame.h"
#include "wire/writer.h"

namespace troupe::testing {

/// A driver that records what it gets and publishes when told. It provides
/// one device of any interface. Commands are counted (a position2d Vel's vx
/// is kept); requests are acknowledged at once, except subtype kNeverReply
/// (never answered) and kReplyLate (answered after 3x the node's request
/// timeout). The test thread asks for ranger scans through burst() and
/// stream(), which wake the node's loop through an eventfd: the publishing
/// itself happens on the node's thread, as it must.
class Recorder : public Driver {
 public:
  static constexpr uint8_t kNeverReply = 99;
  static constexpr uint8_t kReplyLate = 98;

  ~Recorder() override;
  bool setup(Node& node, const DriverSetup& setup, std::string& error) override;
  void on_command(DeviceId device, const wire::Message& cmd) override;
  void on_request(DeviceId device, const wire::Message& req, RequestToken token) override;
  void on_timer(TimerId id) override;
  void on_fd(int fd, uint32_t events) override;

  /// Thread-safe: publish `n` 181-beam scans at once.
  void burst(int n);
  /// Thread-safe: publish a scan every `period_ms` (0: stop).
  void stream(int period_ms);

  std::atomic<int> commands{0};
  std::atomic<int> requests{0};
  std::atomic<float> last_vx{0};
  std::atomic<uint32_t> published{0};

 private:
  void publish_scan(float range_m);

  DeviceId device_ = kNoDevice;
  int wake_fd_ = -1;
  std::atomic<int> pending_burst_{0};
  std::atomic<int> period_ms_{0};
  int running_period_ms_ = 0;
  TimerId stream_ = 0;
  TimerId late_ = 0;
  RequestToken late_token_;
};

/// A Node serving on 127.0.0.1 (port 0: the kernel picks one) in a thread.
class NodeThread {
 public:
  explicit NodeThread(Node::Options options = {});
  ~NodeThread();

  Node& node() { return node_; }
  /// Adds a device served by `driver` (owned by the node after start()).
  DeviceId add_device(wire::Interface iface, uint16_t index, Driver* driver, const char* name = "recorder",
                      uint16_t robot = 0);
  /// Sets up every added driver and starts serving. Fails the test on error.
  void start();
  void stop();
  uint16_t port() const { return port_; }

 private:
  Node node_;
  std::vector<std::pair<Driver*, std::vector<DeviceId>>> pending_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  uint16_t port_ = 0;
};

/// Node::Options for tests: loopback, kernel-chosen port, short deadlines.
Node::Options test_options();

/// The start of most tests: a node serving one Recorder device (robot 0,
/// index 0) and a client connected to it.
struct RecorderNode {
  explicit RecorderNode(wire::Interface iface, Node::Options options = test_options(),
                        client::Client::Options client_options = {});
  NodeThread node;
  Recorder* recorder;
  std::unique_ptr<client::Client> client;
};

/// A plain TCP connection for sending arbitrary bytes and reading frames.
class RawConnection {
 public:
  explicit RawConnection(uint16_t port, int rcvbuf_bytes = 0);
  ~RawConnection();
  bool ok() const { return fd_ >= 0; }
  int fd() const { return fd_; }
  bool send_bytes(std::span<const uint8_t> bytes);
  /// Half-closes: the node sees end of stream but we can still read.
  void shutdown_write();
  /// The next frame within `timeout_ms`, or an empty vector on timeout/EOF.
  std::vector<uint8_t> read_frame(int timeout_ms = 3000);
  /// Reads (and verifies) frames until one of `kind` arrives.
  std::vector<uint8_t> read_until(wire::Kind kind, int timeout_ms = 3000);
  /// True when the node closes the connection within `timeout_ms`.
  bool wait_closed(int timeout_ms = 3000);
  /// Bytes read so far.
  size_t bytes_read() const { return total_; }

 private:
  int fd_ = -1;
  wire::FrameReader reader_{1u << 24};
  size_t total_ = 0;
  bool eof_ = false;
};

/// A frame with the given header and no body.
std::vector<uint8_t> empty_frame(const wire::Address& addr, wire::Kind kind, uint8_t subtype, uint32_t seq);
/// A position2d Vel command frame.
std::vector<uint8_t> vel_frame(const wire::Address& addr, float vx, uint32_t seq);

inline wire::Address addr(wire::Interface iface, uint16_t index = 0, uint16_t robot = 0) {
  return wire::Address(robot, uint16_t(iface), index);
}

}  // namespace troupe::testing
