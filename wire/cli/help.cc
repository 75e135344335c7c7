// `troupe help COMMAND` and `troupe COMMAND --help`.
#include <string>

#include "wire/cli/cli.h"

namespace troupe::cli {

const char* help_text(std::string_view command) {
  if (command == "ls") {
    return "usage: troupe ls HOST[:PORT]\n"
           "\n"
           "Lists the devices of a node or simulator, one per line: the address, a tab,\n"
           "the driver providing it.\n"
           "\n"
           "examples:\n"
           "  troupe ls localhost\n"
           "  troupe ls robot7.local:6670\n";
  }
  if (command == "echo") {
    return "usage: troupe echo HOST[:PORT] ADDR [--count N] [--json] [--pull] [--udp]\n"
           "\n"
           "Prints a device's data as it arrives, one line per message, until N messages\n"
           "or Ctrl-C. Lines start with the sender's time (s) and the sample number.\n"
           "If the node goes away, echo waits and resumes when it is back.\n"
           "\n"
           "  --count N  stop after N messages\n"
           "  --json     the whole message as JSON\n"
           "  --pull     ask for each sample (pull mode) instead of having them pushed\n"
           "  --udp      receive data as UDP datagrams (latest wins)\n"
           "\n"
           "examples:\n"
           "  troupe echo localhost position2d:0 --count 5\n"
           "  troupe echo localhost r3/ranger:1 --json\n";
  }
  if (command == "cmd" || command == "req") {
    static std::string text;
    bool cmd = command == "cmd";
    wire::Kind kind = cmd ? wire::Kind::Command : wire::Kind::Request;
    text = cmd ? "usage: troupe cmd HOST[:PORT] ADDR VERB [ARGS...]\n\nSends a command (no reply).\n"
               : "usage: troupe req HOST[:PORT] ADDR VERB [ARGS...] [--json]\n\n"
                 "Sends a request and prints the reply (\"ok\" when it has no body).\n";
    text += "\nverbs by interface:\n";
    for (uint16_t i = 1; i <= uint16_t(wire::Interface::MAX); ++i) {
      std::string verbs = verb_list(wire::Interface(i), kind);
      if (!verbs.empty()) text += std::string(wire::interface_name(i)) + ":\n" + verbs;
    }
    text += cmd ? "\nexamples:\n  troupe cmd localhost position2d:0 vel 0.3 0 0.2\n"
                  "  troupe cmd localhost r2/position2d:0 goto 1 2 0\n"
                : "\nexamples:\n  troupe req localhost position2d:0 geometry\n"
                  "  troupe req localhost simulation:0 step 10\n";
    return text.c_str();
  }
  if (command == "teleop") {
    return "usage: troupe teleop HOST[:PORT] ADDR\n"
           "\n"
           "Drives a position2d device from the keyboard: w/s (or up/down) change the\n"
           "speed by 0.1 m/s, a/d (or left/right) the turn rate by 0.2 rad/s, space stops,\n"
           "q quits (and stops the robot). The command is re-sent every 100 ms.\n"
           "\n"
           "examples:\n"
           "  troupe teleop localhost position2d:0\n"
           "  troupe teleop localhost:7000 r2/position2d:0   # robot r2 of troupe-sim --port 7000\n";
  }
  return nullptr;
}

}  // namespace troupe::cli
