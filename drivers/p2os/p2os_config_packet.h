// The configuration packet (type 0x20) a P2OS/AROS robot sends when asked
// with CONFIG: its identity, the firmware's top limits and the limits in
// force. ARIA asks for it while connecting and drives under its limits.
// The field order is the one ARIA's ArRobotConfigPacketReader reads (and
// MobileSim/AMRISim write); strings are NUL-terminated, integers
// little-endian. Fields the emulated robot has no use for are sent as 0.
#pragma once

#include <string>

#include "drivers/p2os/p2os_protocol.h"

namespace troupe::drivers::p2os {

struct ConfigPacket {
  std::string robot_class, subclass, serial = "TROUPE", name;
  /// The firmware's absolute maxima: deg/s, mm/s, deg/s^2, mm/s^2.
  int rot_vel_top = 0, trans_vel_top = 0, rot_accel_top = 0, trans_accel_top = 0;
  /// ms between SIPs.
  int sip_cycle_ms = 100;
  /// HOSTBAUD index of the line's speed (0 9600 .. 4 115200).
  int host_baud_index = 0;
  bool front_sonar = true, rear_sonar = true;
  /// Motors stop after this long without a packet, ms.
  int watchdog_ms = 2000;
  /// The limits in force: deg/s, mm/s, deg/s^2, mm/s^2.
  int rot_vel_max = 0, trans_vel_max = 0, rot_accel = 0, rot_decel = 0, trans_accel = 0, trans_decel = 0;
  /// Non-zero: the robot switches its host baud on HOSTBAUD.
  int reset_baud = 1;
  std::string firmware_version = "1.0";
};

/// Frames `c` as a 0x20 packet; false when it does not fit.
bool write_config_packet(const ConfigPacket& c, Packet& out);

}  // namespace troupe::drivers::p2os
