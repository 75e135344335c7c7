// Addresses as people write them: devices "[ROBOT/]INTERFACE:INDEX"
// (Player's style, e.g. "position2d:0", "r3/ranger:1") and hosts
// "HOST[:PORT]" (e.g. "localhost", "10.0.0.7:6670", "[::1]:6665").
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "wire/message.h"

namespace troupe::wire {

/// A device named by a user. `robot` is a robot name or number as written,
/// empty when the text gave none (meaning robot 0).
struct DeviceSpec {
  std::string robot;
  Interface iface = Interface::None;
  uint16_t index = 0;
};

/// Parses "[ROBOT/]INTERFACE:INDEX"; on failure returns false and says why.
bool parse_device(std::string_view text, DeviceSpec& out, std::string& error);

/// The robot number when `robot` is empty or all digits; -1 for a name.
int robot_number(std::string_view robot);

/// "position2d:0" for robot 0 without a name, else "NAME/position2d:0" (or
/// "3/position2d:0" when robot 3 has no name).
std::string format_address(const Address& addr, std::string_view robot_name = {});

struct HostPort {
  std::string host;
  uint16_t port = kDefaultPort;
};

/// Parses "HOST[:PORT]" (IPv6 literals in brackets); on failure returns false.
bool parse_host(std::string_view text, HostPort& out, std::string& error);

}  // namespace troupe::wire
