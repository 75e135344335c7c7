// The recorder behind `troupe record`: opens devices of a node for reading
// and writes their Data frames, as received and with receive times, to a
// log file (log_file.h). It keeps the frames byte for byte, so it takes them
// from the connection core (wire/connection) rather than through the client
// library's decoded handlers. A lost connection is re-established with
// backoff and the devices opened again; the recording goes on in the same file.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "wire/connection/socket_link.h"
#include "wire/record/log_file.h"

namespace troupe::record {

struct RecordOptions {
  std::string host;
  uint16_t port = wire::kDefaultPort;
  /// "[ROBOT/]INTERFACE:INDEX" of each device to record.
  std::vector<std::string> devices;
  std::string output;
  /// Stop after this long, s (0: until stopped).
  double duration_s = 0;
  /// Stop after this many Data frames (0: no limit).
  uint64_t max_frames = 0;
  /// Connection attempts and replies wait this long, ms.
  int timeout_ms = 3000;
  /// Backoff between reconnection attempts doubles from min to max, ms.
  uint32_t reconnect_min_ms = 100;
  uint32_t reconnect_max_ms = 2000;
  /// Looks up the host: every address it gives is tried, in order.
  wire::Resolver resolver = wire::resolve_system;
  /// How cameras are asked to pack their images (Open's `compression`).
  /// The log keeps whatever each image says it is, so a camera that cannot
  /// compress is recorded raw either way.
  wire::ImageCompression image_compression = wire::ImageCompression::None;
  /// A secure session's transport (wire/noise/client_keys.h), under every
  /// connection and reconnection; nullptr: plain TCP.
  std::shared_ptr<wire::Transport> transport;
};

class Recorder {
 public:
  explicit Recorder(RecordOptions options);

  /// Connects, resolves and opens every device, creates the file and writes
  /// the node's Hello and the recorded devices' list. False with `error`
  /// (no host, no such device, cannot create the file): nothing recorded.
  bool start(std::string& error);
  /// Records until the duration or frame count is reached, or `stop_fd`
  /// (-1: none) becomes readable. False with `error` on a write failure.
  bool run(int stop_fd, std::string& error);

  uint64_t frames() const { return frames_; }
  uint64_t bytes() const { return writer_.bytes(); }
  /// Seconds since start().
  double elapsed_s() const;

 private:
  struct Device {
    wire::Address addr;
    std::string name;  // as the user wrote it, for messages
    uint32_t open_seq = 0;
    bool acked = false;
    // Cameras: the Geometry and GetConfig requests whose replies the log
    // keeps, so that play answers them (0: none outstanding).
    uint32_t geometry_seq = 0, config_seq = 0;
  };

  bool resolve(std::string& error);
  void send_opens();
  /// Asks every camera for its geometry and configuration; their Acks go
  /// into the log beside the data.
  void send_camera_requests();
  bool camera_replies_pending() const;
  /// Writes a Data frame of a recorded device; notes Open replies.
  bool handle(std::span<const uint8_t> frame, const wire::Message& msg, std::string& error);
  /// Takes the connection's events until `until` says it has what it waits
  /// for (true), the connection fails or `timeout_ms` passes (false, `error`).
  template <class Until>
  bool wait_for(Until until, int timeout_ms, const char* what, std::string& error);
  bool done() const;

  RecordOptions options_;
  wire::SocketLink link_;
  LogWriter writer_;
  std::vector<Device> devices_;
  std::vector<uint8_t> hello_;        // the node's Hello frame
  std::vector<uint8_t> device_list_;  // the node's DeviceList reply
  uint64_t start_us_ = 0;
  uint64_t frames_ = 0;
  bool lost_ = false;  // the connection dropped and is not back yet
  std::string open_error_;
};

}  // namespace troupe::record
