#include "host-sim/emulators/odrive/fault_console.h"

#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace troupe::emulators::odrive {
namespace {

namespace cs = troupe::cansimple;

constexpr const char* kHelp =
    "commands: silent NODE on|off, error NODE BITS [keep], clear NODE, reboot NODE, drop P, "
    "garbage NODE N, status";

bool parse_number(const std::string& text, unsigned long long& out) {
  if (text.empty()) return false;
  char* end = nullptr;
  out = strtoull(text.c_str(), &end, 0);  // 0x.. hex or decimal
  return end && *end == '\0';
}

}  // namespace

std::string axis_status(const Axis& a) {
  char line[160];
  snprintf(line, sizeof line, "node %u %s error 0x%x %s vel %+.3f turns/s pos %+.3f turns",
           unsigned(a.node_id()), cs::axis_state_name(a.state()), unsigned(a.error()),
           cs::axis_error_name(a.error()), double(a.velocity()), a.position_turns());
  return line;
}

std::string apply_fault_command(OdriveEmulator& emu, std::string_view line, uint64_t now_us) {
  std::istringstream in{std::string(line)};
  std::string verb, first, second, third;
  in >> verb >> first >> second >> third;
  if (verb.empty()) return "";
  if (verb == "help") return kHelp;
  if (verb == "status") {
    std::string out;
    for (const AxisConfig& c : emu.options().axes) {
      if (!out.empty()) out += "\n";
      out += axis_status(*emu.axis(c.node_id));
    }
    return out;
  }
  if (verb == "drop") {
    char* end = nullptr;
    double p = strtod(first.c_str(), &end);
    if (first.empty() || *end != '\0' || !(p >= 0 && p <= 1))
      return "error: drop wants a probability in [0, 1]";
    emu.set_drop_probability(p);
    return "dropping frames with probability " + first;
  }
  if (verb != "silent" && verb != "error" && verb != "clear" && verb != "reboot" && verb != "garbage") {
    return "error: unknown command '" + verb + "' (" + kHelp + ")";
  }
  unsigned long long node = 0;
  if (!parse_number(first, node) || node > cs::kMaxNodeId || emu.axis(uint8_t(node)) == nullptr) {
    return "error: '" + first + "' is not a node id of this bus (" + std::string(kHelp) + ")";
  }
  Axis& axis = *emu.axis(uint8_t(node));
  if (verb == "silent") {
    if (second != "on" && second != "off") return "error: silent NODE on|off";
    emu.set_silent(uint8_t(node), second == "on");
    return "node " + first + (second == "on" ? " silent" : " back on the bus");
  }
  if (verb == "error") {
    unsigned long long bits = 0;
    if (!parse_number(second, bits) || bits == 0 || bits > 0xFFFFFFFFull)
      return "error: error NODE BITS [keep]";
    if (!third.empty() && third != "keep") return "error: the third word of error is 'keep' or nothing";
    axis.inject_error(uint32_t(bits), third == "keep");
    return axis_status(axis);
  }
  if (verb == "clear") {
    axis.clear_fault();
    return "node " + first + ": the cause is gone (the host clears the error)";
  }
  if (verb == "reboot") {
    axis.reboot(now_us);
    return axis_status(axis);
  }
  unsigned long long n = 0;  // garbage
  if (!parse_number(second, n) || n == 0 || n > 10000) return "error: garbage NODE N (1..10000)";
  emu.send_garbage(uint8_t(node), int(n));
  return "sent " + second + " malformed frames as node " + first;
}

}  // namespace troupe::emulators::odrive
