#include "drivers/p2os/p2os_config_packet.h"

namespace troupe::drivers::p2os {
namespace {

// Appends fields to a payload, refusing anything past its end.
class Writer {
 public:
  void u8(int v) {
    if (size_ < kMaxPayloadBytes) buf_[size_++] = uint8_t(v);
    else overflow_ = true;
  }
  void i16(int v) {
    u8(v & 0xFF);
    u8((v >> 8) & 0xFF);
  }
  void str(const std::string& s) {
    for (char c : s) u8(c);
    u8(0);
  }
  bool finish(Packet& out) const { return !overflow_ && make_packet({buf_, size_}, out); }

 private:
  uint8_t buf_[kMaxPayloadBytes];
  size_t size_ = 0;
  bool overflow_ = false;
};

}  // namespace

bool write_config_packet(const ConfigPacket& c, Packet& out) {
  Writer w;
  w.u8(0x20);
  w.str(c.robot_class);
  w.str(c.subclass);
  w.str(c.serial);
  w.u8(0);  // formerly: an AT with P2OS
  w.i16(c.rot_vel_top);
  w.i16(c.trans_vel_top);
  w.i16(c.rot_accel_top);
  w.i16(c.trans_accel_top);
  w.i16(0);  // PWM maximum
  w.str(c.name);
  w.u8(c.sip_cycle_ms);
  w.u8(c.host_baud_index);
  w.u8(0);   // AUX1 baud
  w.i16(0);  // gripper
  w.i16(c.front_sonar ? 1 : 0);
  w.u8(c.rear_sonar ? 1 : 0);
  w.i16(0);  // low battery alarm, 0.1 V
  w.i16(0);  // revolution count
  w.i16(c.watchdog_ms);
  w.u8(0);   // reserved
  w.i16(0);  // stall PWM limit
  w.i16(0);  // stall idle time, ms
  w.i16(0);  // joystick speed
  w.i16(0);  // joystick turn rate
  w.i16(c.rot_vel_max);
  w.i16(c.trans_vel_max);
  w.i16(c.rot_accel);
  w.i16(c.rot_decel);
  for (int i = 0; i < 3; ++i) w.i16(0);  // rotation PID gains
  w.i16(c.trans_accel);
  w.i16(c.trans_decel);
  for (int i = 0; i < 3; ++i) w.i16(0);  // translation PID gains
  w.u8(0);  // front bumper segments
  w.u8(0);  // rear bumper segments
  w.u8(0);  // charger type
  w.u8(0);  // sonar cycle
  w.u8(c.reset_baud);
  w.u8(0);   // has gyro
  w.i16(0);  // drift factor
  w.u8(0);   // AUX2 baud
  w.u8(0);   // AUX3 baud
  w.i16(0);  // encoder ticks per mm
  w.i16(0);  // shutdown voltage
  w.str(c.firmware_version);
  w.i16(0);  // gyro clockwise error
  w.i16(0);  // gyro counter-clockwise error
  w.u8(0);   // kinematics delay
  for (int i = 0; i < 5; ++i) w.i16(0);  // lateral limits (Seekur only)
  w.i16(0);  // charge threshold
  return w.finish(out);
}

}  // namespace troupe::drivers::p2os
