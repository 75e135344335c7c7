// The P2OS/AROS serial protocol of Pioneer robots, as bytes: packets and
// their checksum, command numbers, finding packets in a noisy byte stream,
// and the standard server information packet (SIP) the robot sends every
// 100 ms. No I/O and no allocation; the driver and the robot emulator both
// speak through this. The facts are in protocols.md ("Pioneer P2OS").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace troupe::drivers::p2os {

inline constexpr uint8_t kHeader0 = 0xFA;
inline constexpr uint8_t kHeader1 = 0xFB;
/// A whole packet (header, count, payload, checksum) is at most this, bytes.
inline constexpr size_t kMaxPacketBytes = 200;
/// Largest payload: the packet less header (2), count (1) and checksum (2).
inline constexpr size_t kMaxPayloadBytes = kMaxPacketBytes - 5;

/// Client-to-robot command numbers (the P2OS/AROS manual's, as ARIA names
/// them). The three SYNC numbers are reused once a session is open (0 is
/// PULSE, 1 OPEN, 2 CLOSE).
enum class Command : uint8_t {
  Sync0 = 0,
  Sync1 = 1,
  Sync2 = 2,
  Pulse = 0,
  Open = 1,
  Close = 2,
  Polling = 3,  // string: sonar firing order, transducer numbers from 1
  Enable = 4,
  SetA = 5,   // mm/s^2: positive sets the acceleration, negative the deceleration
  SetV = 6,   // mm/s: top speed of MOVE and VEL
  SetO = 7,   // reset odometry
  Move = 8,   // mm: drive this far and stop
  Rotate = 9, // deg/s, as RVEL
  SetRv = 10, // deg/s: top turn rate of heading moves and RVEL
  Vel = 11,   // mm/s
  Head = 12,  // deg: turn to this odometric heading
  DHead = 13, // deg: turn this far from the current heading
  Say = 15,
  JoyInfo = 17,
  Config = 18,  // ask for the configuration packet (0x20)
  Encoder = 19,
  SetRvDir = 20,
  RVel = 21,    // deg/s
  DcHead = 22,  // deg: move the heading setpoint this far
  SetRA = 23,   // deg/s^2: positive acceleration, negative deceleration
  Sonar = 28,
  Stop = 29,
  DigOut = 30,
  Vel2 = 32,
  Gripper = 33,
  AdSel = 35,
  GripperVal = 36,
  GripRequest = 37,
  IoRequest = 40,
  PtuPos = 41,
  Tty2 = 42,
  GetAux = 43,
  BumpStall = 44,  // 1 front, 2 rear, 3 both rings stop the robot
  Tcm2 = 45,
  JoyDrive = 47,
  MovingBlink = 49,
  HostBaud = 50,  // 0..4: 9600, 19200, 38400, 57600, 115200 bit/s
  Aux1Baud = 51,
  Aux2Baud = 52,
  EStop = 55,
  EStall = 56,
  Gyro = 58,
  BatteryInfo = 62,
};

/// The command's name ("HEAD"), or "unknown" for a number P2OS lacks.
const char* command_name(uint8_t command);

/// The type byte before a command's argument.
enum class ArgType : uint8_t {
  PositiveInt = 0x3B,  // 2 bytes, little-endian
  NegativeInt = 0x1B,  // 2 bytes, little-endian magnitude
  String = 0x2B,       // length byte, then the characters
};

/// Checksum of a payload: the big-endian 16-bit pairs summed modulo 2^16,
/// a last odd byte XORed in. Sent high byte first.
uint16_t checksum(std::span<const uint8_t> payload);

/// A whole packet, built in place.
struct Packet {
  std::array<uint8_t, kMaxPacketBytes> bytes{};
  size_t size = 0;
  std::span<const uint8_t> view() const { return {bytes.data(), size}; }
  std::span<const uint8_t> payload() const { return {bytes.data() + 3, size >= 5 ? size - 5 : 0}; }
};

/// Frames `payload` (1 to kMaxPayloadBytes bytes) as a packet; false when
/// it does not fit.
bool make_packet(std::span<const uint8_t> payload, Packet& out);
/// A command without argument (SYNCs, PULSE, OPEN, CLOSE, STOP, SETO).
Packet command(Command c);
/// A command with an integer argument, clamped to +-32767.
Packet command_int(Command c, int value);
/// VEL2: right and left wheel speeds in units of the robot's Vel2Divisor
/// mm/s, each clamped to +-126. Always sent with the positive-int type:
/// the two signed bytes are the argument (right low, left high).
Packet vel2(int right, int left);

/// An argument read back from a command payload (the emulator's side).
struct CommandArg {
  bool present = false;
  ArgType type = ArgType::PositiveInt;
  /// Integer value, sign applied (PositiveInt/NegativeInt).
  int value = 0;
  /// The two argument bytes as sent, low first.
  uint8_t lo = 0, hi = 0;
};
/// Reads the argument of a command payload ([cmd, type, lo, hi]); `present`
/// is false when the payload carries none or a malformed one.
CommandArg parse_arg(std::span<const uint8_t> payload);

/// Finds packets in a byte stream: hunts for FA FB, checks the count and
/// the checksum, and drops whatever does not frame (line noise, a modem
/// wake-up string, the tail of a torn packet). A packet failing its
/// checksum is dropped and the hunt resumes one byte after its start, so a
/// real packet hidden inside garbage is still found.
class PacketScanner {
 public:
  /// Consumes bytes of `in` up to the end of the next good packet. Returns
  /// the bytes consumed; `payload` is set to the packet's payload when one
  /// completed (valid until the next call), else left empty.
  size_t feed(std::span<const uint8_t> in, std::span<const uint8_t>& payload);
  /// Drops any partial packet (after a baud change or a reopen).
  void reset() { size_ = consume_ = 0; }
  /// Bytes of a packet not yet complete are held.
  bool partial() const { return size_ > consume_; }
  /// Gives up on a partial packet (the sender went quiet in the middle of
  /// it; a corrupted count makes a packet look longer than it is): returns
  /// the next whole packet still held behind it in `payload`, or false when
  /// none is left, the rest dropped.
  bool expire(std::span<const uint8_t>& payload);

  uint32_t packets() const { return packets_; }
  uint32_t bad_checksums() const { return bad_checksums_; }
  /// Bytes dropped while hunting for a header (noise, torn packets).
  uint32_t skipped_bytes() const { return skipped_; }

 private:
  void drop_front(size_t n);
  bool scan(std::span<const uint8_t>& payload);  // looks for a packet in buf_

  uint8_t buf_[kMaxPacketBytes];
  size_t size_ = 0;
  size_t consume_ = 0;  // bytes of the packet handed out last time
  uint32_t packets_ = 0, bad_checksums_ = 0, skipped_ = 0;
};

/// Calls `on_payload(std::span<const uint8_t>)` for every good packet in
/// `in`, in order. The callback may reset the scanner.
template <typename OnPayload>
void scan_packets(PacketScanner& scanner, std::span<const uint8_t> in, OnPayload&& on_payload) {
  for (;;) {
    std::span<const uint8_t> payload;
    in = in.subspan(scanner.feed(in, payload));
    if (!payload.empty()) {
      on_payload(payload);
    } else if (in.empty()) {
      return;
    }
  }
}

/// expire()s a stalled partial packet, calling `on_payload` for every whole
/// packet that was held behind it.
template <typename OnPayload>
void expire_packets(PacketScanner& scanner, OnPayload&& on_payload) {
  for (std::span<const uint8_t> payload; scanner.expire(payload);) on_payload(payload);
}

/// SIP type bytes: 0x32 stopped, 0x33 moving; 0x30-0x34 are standard SIPs.
inline constexpr bool is_standard_sip(uint8_t type) {
  return type >= 0x30 && type <= 0x34;
}

/// One sonar reading of a SIP: transducer index and range in robot counts
/// (times RangeConvFactor gives mm).
struct SonarReading {
  uint8_t index = 0;
  uint16_t range = 0;
};

/// A standard SIP's fields in robot units (see protocols.md for the table).
struct Sip {
  static constexpr size_t kMaxSonar = 32;
  uint8_t type = 0;
  /// Position counters, 15 bits (x DistConvFactor = mm); wrap at 32768.
  uint16_t x = 0, y = 0;
  /// Heading counter (x AngleConvFactor = rad).
  int16_t heading = 0;
  /// Wheel velocities (x VelConvFactor = mm/s).
  int16_t left_vel = 0, right_vel = 0;
  /// Battery, 0.1 V units.
  uint8_t battery = 0;
  bool left_stall = false, right_stall = false;
  /// Bit i: bumper i of the rear / front ring pressed (0..6).
  uint8_t rear_bumpers = 0, front_bumpers = 0;
  uint16_t control = 0, flags = 0;
  uint8_t compass = 0;
  uint8_t sonar_count = 0;
  SonarReading sonar[kMaxSonar];
  /// Timer, analog and digital bytes after the sonar readings; `has_io`
  /// is false on firmware that ends the SIP earlier.
  bool has_io = false;
  uint16_t timer = 0;
  uint8_t analog = 0, digital_in = 0, digital_out = 0;
};

/// Parses a standard SIP payload. False with `why` when the payload is no
/// standard SIP, too short, or names more sonar readings than it carries.
bool parse_sip(std::span<const uint8_t> payload, Sip& out, const char** why);
/// Builds a standard SIP payload (the emulator's side); returns its size,
/// 0 when `sip` does not fit in a packet.
size_t write_sip(const Sip& sip, std::span<uint8_t> out);

/// Name, class and subclass from the SYNC2 reply, NUL-terminated.
struct RobotIdentity {
  char name[64] = {};
  char robot_class[32] = {};
  char subclass[32] = {};
};
/// Reads the SYNC2 reply ([2, name\0, class\0, subclass\0]); false when it
/// is not one. Strings longer than the fields are cut.
bool parse_sync2(std::span<const uint8_t> payload, RobotIdentity& out);

}  // namespace troupe::drivers::p2os
