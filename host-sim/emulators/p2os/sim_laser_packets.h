// MobileSim's laser on the robot's own connection (its "SIM" extension of
// P2OS; AMRISim keeps it). No serial laser exists in the simulator: a
// client enables the simulated laser with a command and the readings come
// in extra server packets after each SIP. Learnt from the public source of
// AMRISim (the server) and ARIA's ArSimulatedLaser (the client):
//
//   client -> robot, each with an integer argument (0x3B/0x1B, LE16):
//     35 or 230  enable: 0 off, 1 plain packets (0x60), 2 extended (0x61)
//     36 or 231  first reading's bearing, degrees from the front (-90)
//     37 or 232  last reading's bearing, degrees (90)
//     38 or 233  degrees between readings x 100 (100)
//   (230-233 carry a laser index byte after the argument; 35-38 are
//   SRISim's older numbers, still what ARIA's ArSimulatedLaser sends.)
//
//   robot -> client, payload after the type byte, little-endian:
//     0x60: x mm i16, y mm i16, heading deg i16 (odometric), total u16,
//           first u16, n u8, n x range mm u16
//     0x61: total u16, first u16, n u8, n x (range mm u16, reflectance u8,
//           2 flag bytes, 0), laser index u8, flags u8 (bit0: the robot
//           moved since the last packet)
//   at most 32 readings a packet, one scan split over as many packets as
//   it takes, `first` counting from 0. A reading with no return is the
//   laser's longest range.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "drivers/p2os/p2os_protocol.h"
#include "host-sim/emulators/serial_line/laser_world.h"

namespace troupe::emulators {

class SimLaserPackets {
 public:
  static constexpr size_t kMaxReadings = 721;
  static constexpr size_t kPerPacket = 32;
  /// Reported for a beam that hits nothing, mm (a SICK LMS200's reach).
  static constexpr uint16_t kNoReturnMm = 8191;

  /// The laser to read; null when the robot has none.
  void attach(LaserWorld* laser) { laser_ = laser; }
  bool attached() const { return laser_ != nullptr; }
  /// A SIM laser command: true when `payload` was one (and obeyed).
  bool obey(std::span<const uint8_t> payload);
  /// 0 off, 1 plain, 2 extended.
  int mode() const { return laser_ ? mode_ : 0; }
  /// The step between beams, degrees.
  double step_deg() const { return step_cdeg_ / 100.0; }

  /// Measures one scan and frames it as packets, calling `send(packet)`
  /// for each. `x_mm`, `y_mm`, `heading_deg` go into plain packets.
  template <typename Send>
  void scan(int x_mm, int y_mm, int heading_deg, bool moved, Send&& send) {
    size_t total = measure();
    drivers::p2os::Packet p;
    for (size_t first = 0; first < total; first += kPerPacket) {
      if (frame(first, total, x_mm, y_mm, heading_deg, moved, p)) send(p);
    }
    ++scans_;
  }
  uint32_t scans() const { return scans_; }

 private:
  size_t measure();
  bool frame(size_t first, size_t total, int x_mm, int y_mm, int heading_deg, bool moved,
             drivers::p2os::Packet& out) const;

  LaserWorld* laser_ = nullptr;
  int mode_ = 0;
  double start_deg_ = -90, end_deg_ = 90;
  int step_cdeg_ = 100;
  uint16_t ranges_mm_[kMaxReadings] = {};
  float ranges_m_[kMaxReadings] = {};
  uint32_t scans_ = 0;
};

}  // namespace troupe::emulators
