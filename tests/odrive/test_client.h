// The odrive bench's view of the node: the device harness's wire client
// (the connection core over loopback, non-blocking, since the node runs in
// the test's own thread) read as position2d and power samples.
#pragma once

#include <cstdint>
#include <string>

#include "tests/device_harness/wire_client.h"

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
  /// Connects to 127.0.0.1:`port`. The node accepts in its loop later.
  bool connect(uint16_t port, std::string& error);
  bool connected() const { return connected_ && !client_.closed(); }

  void open(const wire::Address& addr) { client_.open(addr); }
  /// position2d Vel command: m/s, rad/s.
  void command_vel(const wire::Address& addr, float v, float w) { client_.send_vel(addr, v, w); }
  /// A position2d request; returns the seq its reply will carry.
  uint32_t request_motor_power(const wire::Address& addr, bool on);
  uint32_t request_reset_odometry(const wire::Address& addr);
  uint32_t request_set_odometry(const wire::Address& addr, float x, float y, float a);
  uint32_t request_geometry(const wire::Address& addr);

  /// Reads everything available now. False once the connection failed.
  bool pump();

  /// The newest sample of a device and how many came.
  PositionSample position(const wire::Address& addr) const;
  PowerSample power(const wire::Address& addr) const;
  /// The reply to request `seq`, kind Invalid until it came.
  Reply reply(uint32_t seq) const;
  /// The last Geometry Ack's size: m.
  float geometry_length = 0, geometry_width = 0;

 private:
  WireClient client_;
  bool connected_ = false;
  uint32_t geometry_seq_ = 0;
};

}  // namespace troupe::testing
