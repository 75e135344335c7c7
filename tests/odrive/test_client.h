// A small wire-protocol client for tests that run the node in their own
// thread: every call is non-blocking, pump() reads what has arrived and
// keeps the newest position2d and power data per device, and the replies.
// (The project's client library is the one for programs; this stays
// deliberately small so the node's own tests depend on nothing else.)
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "wire/frame.h"
#include "wire/writer.h"

namespace troupe::testing {

struct PositionSample {
  uint64_t count = 0;  // samples received
  uint32_t seq = 0;
  float x = 0, y = 0, a = 0;  // m, m, rad
  float vx = 0, va = 0;       // m/s, rad/s
  bool stall = false;
  std::string fault;
};

struct PowerSample {
  uint64_t count = 0;
  float volts = 0;  // V
};

struct Reply {
  wire::Kind kind = wire::Kind::Invalid;  // Ack or Nack
  std::string text;                       // Nack reason
};

class TestClient {
 public:
  TestClient() = default;
  ~TestClient();
  TestClient(const TestClient&) = delete;
  TestClient& operator=(const TestClient&) = delete;

  /// Connects to 127.0.0.1:`port`. The node accepts in its loop later.
  bool connect(uint16_t port, std::string& error);
  bool connected() const { return fd_ >= 0; }

  void open(const wire::Address& addr);
  /// position2d Vel command: m/s, rad/s.
  void command_vel(const wire::Address& addr, float v, float w);
  /// A position2d request; returns the seq its reply will carry.
  uint32_t request_motor_power(const wire::Address& addr, bool on);
  uint32_t request_reset_odometry(const wire::Address& addr);
  uint32_t request_set_odometry(const wire::Address& addr, float x, float y, float a);
  uint32_t request_geometry(const wire::Address& addr);

  /// Reads everything available now. False once the connection failed.
  bool pump();

  const PositionSample& position(const wire::Address& addr) { return positions_[wire::address_key(addr)]; }
  const PowerSample& power(const wire::Address& addr) { return powers_[wire::address_key(addr)]; }
  /// The reply to request `seq`, kind Invalid until it came.
  Reply reply(uint32_t seq) const;
  /// The last Geometry Ack's size: m.
  float geometry_length = 0, geometry_width = 0;

 private:
  void send(std::span<const uint8_t> frame);
  void handle(const wire::Message& msg);
  uint32_t request(const wire::Address& addr, wire::Position2dReqSub sub, wire::Body type,
                   flatbuffers::Offset<void> body);

  int fd_ = -1;
  uint32_t seq_ = 0;
  wire::MessageWriter writer_;
  wire::FrameReader reader_{1u << 20};
  std::map<uint64_t, PositionSample> positions_;
  std::map<uint64_t, PowerSample> powers_;
  std::map<uint32_t, Reply> replies_;
};

}  // namespace troupe::testing
