#include "wire/address.h"

#include <charconv>

namespace troupe::wire {
namespace {

bool parse_uint(std::string_view text, uint32_t max, uint32_t& out) {
  if (text.empty()) return false;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc() && end == text.data() + text.size() && out <= max;
}

}  // namespace

bool parse_device(std::string_view text, DeviceSpec& out, std::string& error) {
  out = DeviceSpec{};
  std::string_view rest = text;
  if (auto slash = rest.find('/'); slash != std::string_view::npos) {
    out.robot = std::string(rest.substr(0, slash));
    rest.remove_prefix(slash + 1);
    if (out.robot.empty()) {
      error = "empty robot name in '" + std::string(text) + "'";
      return false;
    }
  }
  auto colon = rest.rfind(':');
  if (colon == std::string_view::npos) {
    error = "address '" + std::string(text) + "' is not [ROBOT/]INTERFACE:INDEX (e.g. position2d:0)";
    return false;
  }
  std::string_view name = rest.substr(0, colon);
  out.iface = interface_from_name(name);
  if (out.iface == Interface::None) {
    error = "unknown interface '" + std::string(name) + "' in '" + std::string(text) + "'";
    return false;
  }
  uint32_t index = 0;
  if (!parse_uint(rest.substr(colon + 1), 0xFFFF, index)) {
    error = "bad index in '" + std::string(text) + "' (want 0..65535)";
    return false;
  }
  out.index = static_cast<uint16_t>(index);
  return true;
}

int robot_number(std::string_view robot) {
  if (robot.empty()) return 0;
  uint32_t n = 0;
  return parse_uint(robot, 0xFFFF, n) ? static_cast<int>(n) : -1;
}

std::string format_address(const Address& addr, std::string_view robot_name) {
  std::string out;
  if (!robot_name.empty()) {
    out.append(robot_name).push_back('/');
  } else if (addr.robot() != 0) {
    out.append(std::to_string(addr.robot())).push_back('/');
  }
  out.append(interface_name(addr.iface())).push_back(':');
  out.append(std::to_string(addr.index()));
  return out;
}

bool parse_host(std::string_view text, HostPort& out, std::string& error) {
  out = HostPort{};
  std::string_view host = text;
  std::string_view port;
  if (!text.empty() && text.front() == '[') {
    auto close = text.find(']');
    if (close == std::string_view::npos) {
      error = "missing ']' in '" + std::string(text) + "'";
      return false;
    }
    host = text.substr(1, close - 1);
    std::string_view after = text.substr(close + 1);
    if (!after.empty()) {
      if (after.front() != ':') {
        error = "unexpected text after ']' in '" + std::string(text) + "'";
        return false;
      }
      port = after.substr(1);
      if (port.empty()) {
        error = "empty port in '" + std::string(text) + "'";
        return false;
      }
    }
  } else if (auto colon = text.find(':'); colon != std::string_view::npos) {
    if (text.find(':', colon + 1) != std::string_view::npos) {
      error = "IPv6 addresses need brackets: [" + std::string(text) + "]";
      return false;
    }
    host = text.substr(0, colon);
    port = text.substr(colon + 1);
    if (port.empty()) {
      error = "empty port in '" + std::string(text) + "'";
      return false;
    }
  }
  if (host.empty()) {
    error = "empty host name";
    return false;
  }
  out.host = std::string(host);
  if (!port.empty()) {
    uint32_t p = 0;
    if (!parse_uint(port, 65535, p) || p == 0) {
      error = "bad port '" + std::string(port) + "' (want 1..65535)";
      return false;
    }
    out.port = static_cast<uint16_t>(p);
  }
  return true;
}

}  // namespace troupe::wire
