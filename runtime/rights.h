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
inline const char* right_name(Right right) {
  return right == Right::Read ? "read" : right == Right::Command ? "command" : "request";
}

/// What one client may do. An interface, so that a node built without
/// secure sessions (a small board's) links none of the pattern matching.
class Rights {
 public:
  virtual ~Rights() = default;
  /// Whether the client holds `right` on device `addr`, whose robot the
  /// node calls `robot_name` (may be empty).
  virtual bool allows(Right right, const wire::Address& addr, std::string_view robot_name) const = 0;
  /// allows(), and when not, `refusal` says so for the client's Nack.
  bool permits(Right right, const wire::Address& addr, std::string_view robot_name, std::string& refusal) const;
};

/// A set of devices as a person writes it: "[ROBOT/]INTERFACE:INDEX" like an
/// address, where any part may be "*" ("position2d:*", "*/ranger:0"), or "*"
/// alone for every device. Without a robot part it means robot 0, as an
/// address does. The robot is a number or the name the node gives it.
struct DevicePattern {
  bool any_robot = false;
  std::string robot;         // as written, unless any_robot; empty: robot 0
  int32_t robot_number = 0;  // `robot` as a number, -1 when it is a name
  uint16_t iface = 0;  // wire::Interface; 0 (None): any
  int32_t index = -1;  // -1: any

  /// Parses `text`; false with `error` saying what is wrong with it.
  static bool parse(std::string_view text, DevicePattern& out, std::string& error);
  bool matches(const wire::Address& addr, std::string_view robot_name) const;
};

/// Rights as a node config grants them: per right, the device patterns it
/// holds it on.
class PatternRights final : public Rights {
 public:
  /// Every right on every device: a client listed without rights.
  static PatternRights all();

  void grant(Right right, DevicePattern devices) { granted_[int(right)].push_back(std::move(devices)); }
  bool allows(Right right, const wire::Address& addr, std::string_view robot_name) const override;

 private:
  std::vector<DevicePattern> granted_[3];
};

}  // namespace troupe
