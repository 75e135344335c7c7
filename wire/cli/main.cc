// troupe: the command-line client. `troupe help` lists the commands.
#include <unistd.h>

#include <algorithm>
#include <climits>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "wire/cli/cli.h"

namespace {

using troupe::cli::cmd_echo;
using troupe::cli::cmd_keygen;
using troupe::cli::cmd_ls;
using troupe::cli::cmd_teleop;

int cmd_command(const std::vector<std::string>& args) {
  return troupe::cli::cmd_send(args, troupe::wire::Kind::Command);
}
int cmd_request(const std::vector<std::string>& args) {
  return troupe::cli::cmd_send(args, troupe::wire::Kind::Request);
}

/// A subcommand: built in (run), or the program troupe-NAME (run is null).
struct Command {
  const char* name;
  const char* synopsis;
  const char* summary;
  int (*run)(const std::vector<std::string>& args);
};

// The programs are the tools of this tree that are meant for users; any
// other troupe-NAME on the PATH works the same way without being listed.
constexpr Command kCommands[] = {
    {"ls", "HOST", "list the devices of a node or simulator", cmd_ls},
    {"echo", "HOST ADDR", "print data as it arrives, one line each", cmd_echo},
    {"cmd", "HOST ADDR VERB ARGS", "send a command (e.g. vel 0.3 0 0.2)", cmd_command},
    {"req", "HOST ADDR VERB ARGS", "send a request and print its reply", cmd_request},
    {"teleop", "HOST ADDR", "drive a position2d device with the keyboard", cmd_teleop},
    {"keygen", "NAME", "write a key pair for secure sessions (NAME, NAME.pub)", cmd_keygen},
    {"record", "HOST ADDR... -o FILE", "record devices' data to a log file", nullptr},
    {"play", "FILE", "serve a recorded log again, as a node", nullptr},
    {"sim", "WORLD", "simulate a Stage world and serve its robots", nullptr},
    {"node", "CONFIG", "run a device server (troupe-node)", nullptr},
    {"config", "compile|print CONFIG", "compile a node config for a board, or show one", nullptr},
    {"view", "HOST", "the browser viewer for a live node", nullptr},
    {"logmap", "LOG -o MAP.png", "draw an occupancy map from a CARMEN log", nullptr},
    {"mcl-eval", "LOG", "Monte Carlo localization on a CARMEN log, scored", nullptr},
    {"ros2", "HOST", "publish every device of a node or simulator on ROS 2", nullptr},
    {"robocup", "WORLD", "a RoboCup world flat out, from the console (troupe-sim)", nullptr},
    {"goalkeeper-bench", "", "the goalkeeper benchmark table", nullptr},
    {"robocup-motion", "record|fit|check", "train and check the learned motion model", nullptr},
    {"emulate-p2os", "", "a Pioneer (P2OS) on a pseudo-terminal", nullptr},
    {"emulate-sick", "", "a SICK LMS200 on a pseudo-terminal", nullptr},
    {"emulate-odrive", "--can IFACE", "ODrive axes on a CAN bus", nullptr},
};

std::string usage_text() {
  std::string text = "usage: troupe COMMAND ARGS...\n\n";
  auto line = [&](const Command& c) {
    std::string head = std::string(c.name) + " " + c.synopsis;
    head.resize(std::max<size_t>(head.size() + 1, 33), ' ');
    text += "  " + head + c.summary + "\n";
  };
  for (const Command& c : kCommands) {
    if (c.run != nullptr) line(c);
  }
  line({"help", "COMMAND", "details and examples of a command", nullptr});
  text += "\nprograms run as troupe-COMMAND (next to troupe, else on the PATH):\n";
  for (const Command& c : kCommands) {
    if (c.run == nullptr) line(c);
  }
  text +=
      "\n"
      "HOST is HOST[:PORT] (port 6665 by default); ADDR is [ROBOT/]INTERFACE:INDEX,\n"
      "e.g. position2d:0 or r3/ranger:1. Any other troupe-COMMAND on the PATH is a\n"
      "command too.\n"
      "\n"
      "examples:\n"
      "  troupe sim examples/worlds/room.world &\n"
      "  troupe ls localhost\n"
      "  troupe cmd localhost r0/position2d:0 vel 0.3 0 0.2\n"
      "  troupe echo localhost r0/ranger:0 --count 3\n"
      "  troupe help record\n";
  return text;
}

// Runs troupe-<name> from this program's folder, else from PATH (git's way
// of growing subcommands without this file knowing them).
int run_external(const std::string& name, std::vector<std::string> rest) {
  std::string program = "troupe-" + name;
  std::vector<char*> args;
  args.push_back(program.data());
  for (std::string& a : rest) args.push_back(a.data());
  args.push_back(nullptr);
  char self[PATH_MAX];
  ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n > 0) {
    self[n] = '\0';
    std::string dir(self);
    dir.resize(dir.rfind('/') + 1);
    std::string sibling = dir + program;
    execv(sibling.c_str(), args.data());
  }
  execvp(program.c_str(), args.data());
  fprintf(stderr, "troupe: unknown command '%s' (no program %s; see: troupe help)\n", name.c_str(),
          program.c_str());
  return troupe::cli::kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    fputs(usage_text().c_str(), stderr);
    return troupe::cli::kExitUsage;
  }
  std::string command = argv[1];
  std::vector<std::string> args(argv + 2, argv + argc);
  if (command == "-h" || command == "--help" || (command == "help" && args.empty())) {
    fputs(usage_text().c_str(), stdout);
    return 0;
  }
  if (command == "help") {
    command = args[0];
    args = {"--help"};
  }
  for (const Command& c : kCommands) {
    if (c.run != nullptr && command == c.name) return c.run(args);
  }
  return run_external(command, args);
}
