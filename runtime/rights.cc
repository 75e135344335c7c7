#include "runtime/rights.h"

#include <charconv>

#include "wire/address.h"

namespace troupe {

bool Rights::permits(Right right, const wire::Address& addr, std::string_view robot_name,
                     std::string& refusal) const {
  if (allows(right, addr, robot_name)) return true;
  refusal = std::string("this client may not ") + right_name(right) + " " + wire::format_address(addr, robot_name) +
            " (the node's \"clients\" config)";
  return false;
}

bool DevicePattern::parse(std::string_view text, DevicePattern& out, std::string& error) {
  out = DevicePattern{};
  auto fail = [&](const std::string& why) {
    error = "device pattern '" + std::string(text) + "'" + why;
    return false;
  };
  if (text == "*") {
    out.any_robot = true;
    return true;
  }
  std::string_view rest = text;
  if (const size_t slash = rest.find('/'); slash != std::string_view::npos) {
    const std::string_view robot = rest.substr(0, slash);
    if (robot.empty()) return fail(": empty robot before '/'");
    out.any_robot = robot == "*";
    if (!out.any_robot) out.robot = std::string(robot);
    // The number is read once here: the check runs for every message.
    out.robot_number = out.any_robot ? 0 : wire::robot_number(robot);
    rest.remove_prefix(slash + 1);
  }
  const size_t colon = rest.rfind(':');
  if (colon == std::string_view::npos) {
    return fail(" is not [ROBOT/]INTERFACE:INDEX with '*' for any part (e.g. position2d:*), or '*'");
  }
  const std::string_view iface = rest.substr(0, colon), index = rest.substr(colon + 1);
  if (iface != "*") {
    out.iface = uint16_t(wire::interface_from_name(iface));
    if (out.iface == uint16_t(wire::Interface::None)) return fail(": unknown interface '" + std::string(iface) + "'");
  }
  if (index != "*") {
    uint32_t n = 0;
    auto [end, ec] = std::from_chars(index.data(), index.data() + index.size(), n);
    if (index.empty() || ec != std::errc() || end != index.data() + index.size() || n > 0xFFFF) {
      return fail(": bad index '" + std::string(index) + "' (want 0..65535 or *)");
    }
    out.index = int32_t(n);
  }
  return true;
}

bool DevicePattern::matches(const wire::Address& addr, std::string_view robot_name) const {
  const bool named = !robot.empty() && robot == robot_name;
  const bool robot_matches = any_robot || named || (robot_number >= 0 && addr.robot() == robot_number);
  if (!robot_matches) return false;
  if (iface != 0 && iface != addr.iface()) return false;
  return index < 0 || index == addr.index();
}

PatternRights PatternRights::all() {
  PatternRights r;
  DevicePattern every;
  every.any_robot = true;
  for (Right right : {Right::Read, Right::Command, Right::Request}) r.grant(right, every);
  return r;
}

bool PatternRights::allows(Right right, const wire::Address& addr, std::string_view robot_name) const {
  for (const DevicePattern& p : granted_[int(right)]) {
    if (p.matches(addr, robot_name)) return true;
  }
  return false;
}

}  // namespace troupe
