// What a client of a secure node may do, device by device: the rights its
// entry in the node config's "clients" grants (wire/README.md, "Rights").
// The node checks them where it routes a client's Open, Pull, Command and
// Request; a refusal is a Nack Forbidden and the connection goes on.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "wire/message.h"

namespace troupe {

enum class Right : uint8_t {
  Read,     // open a device for its data, pull its data
  Command,  // send it commands
  Request,  // send it requests (configuration, geometry, simulation control)
};
/// "read", "command", "request".
const char* right_name(Right right);

/// A set of devices as a person writes it: "[ROBOT/]INTERFACE:INDEX" like an
/// address, where any part may be "*" ("position2d:*", "*/ranger:0"), or "*"
/// alone for every device. Without a robot part it means robot 0, as an
/// address does. The robot is a number or the name the node gives it.
struct DevicePattern {
  bool any_robot = false;
  std::string robot;  // unless any_robot; empty: robot 0
  uint16_t iface = 0;  // wire::Interface; 0 (None): any
  int32_t index = -1;  // -1: any

  /// Parses `text`; false with `error` saying what is wrong with it.
  static bool parse(std::string_view text, DevicePattern& out, std::string& error);
  /// Whether device `addr`, whose robot the node calls `robot_name` (may be
  /// empty), is one of the set.
  bool matches(const wire::Address& addr, std::string_view robot_name) const;
};

/// The rights of one client: per right, the devices it holds it on.
class Rights {
 public:
  /// Every right on every device: a client listed without rights.
  static Rights all();

  void grant(Right right, DevicePattern devices) { granted_[int(right)].push_back(std::move(devices)); }
  bool allows(Right right, const wire::Address& addr, std::string_view robot_name) const;

 private:
  std::vector<DevicePattern> granted_[3];
};

}  // namespace troupe
