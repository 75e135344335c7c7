// A small blocking wire client for the cross tests: TCP to a node on
// loopback, frames cut with wire::FrameReader and checked with
// wire::verify_frame, messages built with wire::MessageWriter. (The C++
// client library can take its place once it is in main.)
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "wire/frame.h"
#include "wire/writer.h"

namespace troupe::cross {

class TestClient {
 public:
  TestClient() : reader_(1u << 20) {}
  ~TestClient();
  TestClient(const TestClient&) = delete;
  TestClient& operator=(const TestClient&) = delete;

  /// Connects to 127.0.0.1:`port`, reads the node's Hello and answers it.
  /// False with `error`.
  bool connect(uint16_t port, std::string& error);
  /// The name the node gave in its Hello.
  const std::string& node_name() const { return node_name_; }

  /// Sends bytes as they are (a frame, or deliberately broken input).
  bool send_raw(std::span<const uint8_t> bytes);
  /// Sends the message built in writer() since writer().start().
  bool send(const wire::Header& header, wire::Body type = wire::Body::NONE,
            flatbuffers::Offset<void> body = 0);
  wire::MessageWriter& writer() { return writer_; }

  /// The next verified message, waiting at most `timeout_ms`; nullptr on
  /// timeout, close or a frame that fails verification (see error()). Valid
  /// until the next call.
  const wire::Message* next(int timeout_ms = 10000);
  /// Skips messages until one of `kind` with sequence `seq` arrives.
  const wire::Message* reply(wire::Kind kind, uint32_t seq, int timeout_ms = 10000);
  /// Skips messages until a Data message of `addr` arrives.
  const wire::Message* data(const wire::Address& addr, int timeout_ms = 10000);
  /// True once the node closed the connection.
  bool closed() const { return closed_; }
  const std::string& error() const { return error_; }

  /// Asks for the device list; false when no list came.
  bool list_devices(std::vector<wire::Address>& out, std::vector<std::string>& drivers);
  /// Opens a device; true on Ack.
  bool open(const wire::Address& addr, wire::Access access = wire::Access::All,
            wire::Delivery delivery = wire::Delivery::Push);
  /// Sends Position2d Command/Vel: m/s forward, rad/s.
  bool send_vel(const wire::Address& addr, float v, float w);
  uint32_t next_seq() { return ++seq_; }

 private:
  int fd_ = -1;
  wire::FrameReader reader_;
  wire::MessageWriter writer_;
  std::vector<uint8_t> current_;
  std::string node_name_;
  std::string error_;
  uint32_t seq_ = 0;
  bool closed_ = false;
};

}  // namespace troupe::cross
