#include "host-sim/emulators/p2os/sim_laser_packets.h"

#include <algorithm>
#include <cmath>

namespace troupe::emulators {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

void put_le16(uint8_t* p, int v) {
  p[0] = uint8_t(v & 0xFF);
  p[1] = uint8_t((v >> 8) & 0xFF);
}

}  // namespace

bool SimLaserPackets::obey(std::span<const uint8_t> payload) {
  const uint8_t cmd = payload[0];
  const bool old_number = cmd >= 35 && cmd <= 38, new_number = cmd >= 230 && cmd <= 233;
  if (!laser_ || !(old_number || new_number)) return false;
  drivers::p2os::CommandArg arg = drivers::p2os::parse_arg(payload);
  if (!arg.present) return true;  // malformed: ignored, as the firmware does
  switch (old_number ? cmd - 35 : cmd - 230) {
    case 0:
      mode_ = std::clamp(arg.value, 0, 2);
      break;
    case 1:
      start_deg_ = std::clamp(arg.value, -180, 180);
      break;
    case 2:
      end_deg_ = std::clamp(arg.value, -180, 180);
      break;
    case 3:
      // A step too fine for the packets' reading count is coarsened.
      step_cdeg_ = std::max(arg.value, 1);
      break;
  }
  return true;
}

size_t SimLaserPackets::measure() {
  double lo = std::min(start_deg_, end_deg_), hi = std::max(start_deg_, end_deg_);
  size_t total = size_t(std::floor((hi - lo) * 100.0 / step_cdeg_ + 1e-9)) + 1;
  total = std::min(total, kMaxReadings);
  laser_->measure(lo * kDegToRad, step_deg() * kDegToRad, {ranges_m_, total});
  for (size_t i = 0; i < total; ++i) {
    double mm = std::round(double(ranges_m_[i]) * 1000.0);
    ranges_mm_[i] = !std::isfinite(mm) || mm >= kNoReturnMm ? kNoReturnMm : uint16_t(std::max(mm, 0.0));
  }
  return total;
}

bool SimLaserPackets::frame(size_t first, size_t total, int x_mm, int y_mm, int heading_deg, bool moved,
                            drivers::p2os::Packet& out) const {
  const bool extended = mode_ == 2;
  const size_t n = std::min(kPerPacket, total - first);
  uint8_t payload[drivers::p2os::kMaxPayloadBytes];
  size_t at = 0;
  payload[at++] = extended ? 0x61 : 0x60;
  if (!extended) {
    put_le16(payload + at, x_mm);
    put_le16(payload + at + 2, y_mm);
    put_le16(payload + at + 4, heading_deg);
    at += 6;
  }
  put_le16(payload + at, int(total));
  put_le16(payload + at + 2, int(first));
  payload[at + 4] = uint8_t(n);
  at += 5;
  for (size_t i = 0; i < n; ++i) {
    put_le16(payload + at, ranges_mm_[first + i]);
    at += 2;
    if (extended) {
      payload[at++] = 0;  // reflectance: the simulated world has none
      payload[at++] = 0;
      payload[at++] = 0;
    }
  }
  if (extended) {
    payload[at++] = 0;  // laser index
    payload[at++] = moved ? 1 : 0;
  }
  return drivers::p2os::make_packet({payload, at}, out);
}

}  // namespace troupe::emulators
