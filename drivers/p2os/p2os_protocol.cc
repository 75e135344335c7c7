#include "drivers/p2os/p2os_protocol.h"

#include <algorithm>
#include <cstring>

namespace troupe::drivers::p2os {
namespace {

uint16_t le16(const uint8_t* p) {
  return uint16_t(p[0] | (p[1] << 8));
}

void put_le16(uint8_t* p, uint16_t v) {
  p[0] = uint8_t(v & 0xFF);
  p[1] = uint8_t(v >> 8);
}

// Byte offsets of a standard SIP payload (protocols.md).
constexpr size_t kSipX = 1, kSipY = 3, kSipHeading = 5, kSipLeftVel = 7, kSipRightVel = 9, kSipBattery = 11,
                 kSipLeftStall = 12, kSipRightStall = 13, kSipControl = 14, kSipFlags = 16, kSipCompass = 18,
                 kSipSonarCount = 19, kSipSonar = 20;
constexpr size_t kSonarBytes = 3;  // index u8, range u16
constexpr size_t kIoBytes = 5;     // timer u16, analog, digital in, digital out

}  // namespace

const char* command_name(uint8_t command) {
  switch (Command(command)) {
    case Command::Pulse: return "PULSE";
    case Command::Open: return "OPEN";
    case Command::Close: return "CLOSE";
    case Command::Polling: return "POLLING";
    case Command::Enable: return "ENABLE";
    case Command::SetA: return "SETA";
    case Command::SetV: return "SETV";
    case Command::SetO: return "SETO";
    case Command::Move: return "MOVE";
    case Command::Rotate: return "ROTATE";
    case Command::SetRv: return "SETRV";
    case Command::Vel: return "VEL";
    case Command::Head: return "HEAD";
    case Command::DHead: return "DHEAD";
    case Command::Say: return "SAY";
    case Command::JoyInfo: return "JOYINFO";
    case Command::Config: return "CONFIG";
    case Command::Encoder: return "ENCODER";
    case Command::SetRvDir: return "SETRVDIR";
    case Command::RVel: return "RVEL";
    case Command::DcHead: return "DCHEAD";
    case Command::SetRA: return "SETRA";
    case Command::Sonar: return "SONAR";
    case Command::Stop: return "STOP";
    case Command::DigOut: return "DIGOUT";
    case Command::Vel2: return "VEL2";
    case Command::Gripper: return "GRIPPER";
    case Command::AdSel: return "ADSEL";
    case Command::GripperVal: return "GRIPPERVAL";
    case Command::GripRequest: return "GRIPREQUEST";
    case Command::IoRequest: return "IOREQUEST";
    case Command::PtuPos: return "PTUPOS";
    case Command::Tty2: return "TTY2";
    case Command::GetAux: return "GETAUX";
    case Command::BumpStall: return "BUMPSTALL";
    case Command::Tcm2: return "TCM2";
    case Command::JoyDrive: return "JOYDRIVE";
    case Command::MovingBlink: return "MOVINGBLINK";
    case Command::HostBaud: return "HOSTBAUD";
    case Command::Aux1Baud: return "AUX1BAUD";
    case Command::Aux2Baud: return "AUX2BAUD";
    case Command::EStop: return "ESTOP";
    case Command::EStall: return "ESTALL";
    case Command::Gyro: return "GYRO";
    case Command::BatteryInfo: return "BATTERYINFO";
  }
  return "unknown";
}

uint16_t checksum(std::span<const uint8_t> payload) {
  uint32_t sum = 0;
  size_t i = 0;
  for (; i + 1 < payload.size(); i += 2) {
    sum = (sum + ((uint32_t(payload[i]) << 8) | payload[i + 1])) & 0xFFFF;
  }
  if (i < payload.size()) sum ^= payload[i];
  return uint16_t(sum);
}

bool make_packet(std::span<const uint8_t> payload, Packet& out) {
  if (payload.empty() || payload.size() > kMaxPayloadBytes) return false;
  out.bytes[0] = kHeader0;
  out.bytes[1] = kHeader1;
  out.bytes[2] = uint8_t(payload.size() + 2);
  memcpy(out.bytes.data() + 3, payload.data(), payload.size());
  uint16_t sum = checksum(payload);
  out.bytes[3 + payload.size()] = uint8_t(sum >> 8);
  out.bytes[4 + payload.size()] = uint8_t(sum & 0xFF);
  out.size = payload.size() + 5;
  return true;
}

Packet command(Command c) {
  Packet p;
  uint8_t payload[1] = {uint8_t(c)};
  make_packet(payload, p);
  return p;
}

Packet command_int(Command c, int value) {
  value = std::clamp(value, -32767, 32767);
  uint16_t magnitude = uint16_t(value < 0 ? -value : value);
  uint8_t payload[4] = {uint8_t(c), uint8_t(value < 0 ? ArgType::NegativeInt : ArgType::PositiveInt),
                        uint8_t(magnitude & 0xFF), uint8_t(magnitude >> 8)};
  Packet p;
  make_packet(payload, p);
  return p;
}

Packet vel2(int right, int left) {
  right = std::clamp(right, -126, 126);
  left = std::clamp(left, -126, 126);
  uint8_t payload[4] = {uint8_t(Command::Vel2), uint8_t(ArgType::PositiveInt), uint8_t(int8_t(right)),
                        uint8_t(int8_t(left))};
  Packet p;
  make_packet(payload, p);
  return p;
}

CommandArg parse_arg(std::span<const uint8_t> payload) {
  CommandArg arg;
  if (payload.size() < 4) return arg;
  uint8_t type = payload[1];
  if (type != uint8_t(ArgType::PositiveInt) && type != uint8_t(ArgType::NegativeInt)) return arg;
  arg.present = true;
  arg.type = ArgType(type);
  arg.lo = payload[2];
  arg.hi = payload[3];
  int magnitude = le16(&payload[2]);
  arg.value = arg.type == ArgType::NegativeInt ? -magnitude : magnitude;
  return arg;
}

void PacketScanner::drop_front(size_t n) {
  n = std::min(n, size_);
  memmove(buf_, buf_ + n, size_ - n);
  size_ -= n;
}

bool PacketScanner::scan(std::span<const uint8_t>& payload) {
  for (;;) {
    // Hunt for the header.
    size_t start = 0;
    while (start < size_ && buf_[start] != kHeader0) ++start;
    if (start > 0) {
      skipped_ += uint32_t(start);
      drop_front(start);
    }
    if (size_ < 2) return false;
    if (buf_[1] != kHeader1) {
      ++skipped_;
      drop_front(1);
      continue;
    }
    if (size_ < 3) return false;
    size_t count = buf_[2];
    // A count under 3 has no room for a command byte; over the limit it
    // cannot be a packet. Either way this FA FB was noise.
    if (count < 3 || count + 3 > kMaxPacketBytes) {
      ++skipped_;
      drop_front(1);
      continue;
    }
    if (size_ < count + 3) return false;
    std::span<const uint8_t> body(buf_ + 3, count - 2);
    uint16_t sum = uint16_t((buf_[count + 1] << 8) | buf_[count + 2]);
    if (checksum(body) != sum) {
      ++bad_checksums_;
      drop_front(1);
      continue;
    }
    ++packets_;
    payload = body;
    consume_ = count + 3;
    return true;
  }
}

size_t PacketScanner::feed(std::span<const uint8_t> in, std::span<const uint8_t>& payload) {
  payload = {};
  if (consume_ > 0) {
    drop_front(consume_);
    consume_ = 0;
    // Bytes left after the last packet may already hold the next one.
    if (scan(payload)) return 0;
  }
  size_t used = 0;
  while (used < in.size()) {
    size_t take = std::min(in.size() - used, kMaxPacketBytes - size_);
    memcpy(buf_ + size_, in.data() + used, take);
    size_ += take;
    used += take;
    if (scan(payload)) {
      // Hand back the bytes after this packet that were copied in but not
      // yet looked at: the caller feeds them again.
      size_t extra = size_ - consume_;
      size_t give_back = std::min(extra, take);
      size_ -= give_back;
      return used - give_back;
    }
  }
  return used;
}

bool PacketScanner::expire(std::span<const uint8_t>& payload) {
  if (consume_ > 0) {
    drop_front(consume_);
    consume_ = 0;
  }
  while (size_ > 0) {
    if (scan(payload)) return true;
    // The packet at the front will not complete: hunt on past its header.
    ++skipped_;
    drop_front(1);
  }
  return false;
}

bool parse_sip(std::span<const uint8_t> p, Sip& out, const char** why) {
  auto fail = [why](const char* text) {
    if (why) *why = text;
    return false;
  };
  if (p.empty() || !is_standard_sip(p[0])) return fail("not a standard SIP");
  if (p.size() < kSipSonar) return fail("SIP shorter than its fixed fields");
  out.type = p[0];
  out.x = le16(&p[kSipX]) & 0x7FFF;
  out.y = le16(&p[kSipY]) & 0x7FFF;
  out.heading = int16_t(le16(&p[kSipHeading]));
  out.left_vel = int16_t(le16(&p[kSipLeftVel]));
  out.right_vel = int16_t(le16(&p[kSipRightVel]));
  out.battery = p[kSipBattery];
  out.left_stall = p[kSipLeftStall] & 1;
  out.rear_bumpers = p[kSipLeftStall] >> 1;
  out.right_stall = p[kSipRightStall] & 1;
  out.front_bumpers = p[kSipRightStall] >> 1;
  out.control = le16(&p[kSipControl]);
  out.flags = le16(&p[kSipFlags]);
  out.compass = p[kSipCompass];
  size_t n = p[kSipSonarCount];
  if (n > Sip::kMaxSonar) return fail("SIP names more sonar readings than a robot has");
  if (kSipSonar + n * kSonarBytes > p.size()) return fail("SIP names more sonar readings than it carries");
  out.sonar_count = uint8_t(n);
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* r = &p[kSipSonar + i * kSonarBytes];
    out.sonar[i] = {r[0], le16(r + 1)};
  }
  size_t io = kSipSonar + n * kSonarBytes;
  out.has_io = p.size() >= io + kIoBytes;
  if (out.has_io) {
    out.timer = le16(&p[io]);
    out.analog = p[io + 2];
    out.digital_in = p[io + 3];
    out.digital_out = p[io + 4];
  }
  return true;
}

size_t write_sip(const Sip& s, std::span<uint8_t> out) {
  size_t size = kSipSonar + s.sonar_count * kSonarBytes + kIoBytes;
  if (s.sonar_count > Sip::kMaxSonar || size > out.size() || size > kMaxPayloadBytes) return 0;
  uint8_t* p = out.data();
  p[0] = s.type;
  put_le16(p + kSipX, s.x & 0x7FFF);
  put_le16(p + kSipY, s.y & 0x7FFF);
  put_le16(p + kSipHeading, uint16_t(s.heading));
  put_le16(p + kSipLeftVel, uint16_t(s.left_vel));
  put_le16(p + kSipRightVel, uint16_t(s.right_vel));
  p[kSipBattery] = s.battery;
  p[kSipLeftStall] = uint8_t((s.left_stall ? 1 : 0) | (s.rear_bumpers << 1));
  p[kSipRightStall] = uint8_t((s.right_stall ? 1 : 0) | (s.front_bumpers << 1));
  put_le16(p + kSipControl, s.control);
  put_le16(p + kSipFlags, s.flags);
  p[kSipCompass] = s.compass;
  p[kSipSonarCount] = s.sonar_count;
  for (size_t i = 0; i < s.sonar_count; ++i) {
    uint8_t* r = p + kSipSonar + i * kSonarBytes;
    r[0] = s.sonar[i].index;
    put_le16(r + 1, s.sonar[i].range);
  }
  uint8_t* io = p + kSipSonar + s.sonar_count * kSonarBytes;
  put_le16(io, s.timer);
  io[2] = s.analog;
  io[3] = s.digital_in;
  io[4] = s.digital_out;
  return size;
}

bool parse_sync2(std::span<const uint8_t> p, RobotIdentity& out) {
  if (p.empty() || p[0] != uint8_t(Command::Sync2)) return false;
  out = RobotIdentity{};
  char* fields[3] = {out.name, out.robot_class, out.subclass};
  size_t sizes[3] = {sizeof out.name, sizeof out.robot_class, sizeof out.subclass};
  size_t pos = 1;
  for (int f = 0; f < 3; ++f) {
    size_t len = 0;
    while (pos < p.size() && p[pos] != 0) {
      if (len + 1 < sizes[f]) fields[f][len++] = char(p[pos]);
      ++pos;
    }
    if (pos >= p.size()) return f == 2 && len > 0;  // the last string may lack its NUL
    ++pos;
  }
  return true;
}

}  // namespace troupe::drivers::p2os
