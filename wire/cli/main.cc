// troupe: the command-line client. `troupe help` lists the commands.
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "wire/cli/cli.h"

namespace {

const char kUsage[] =
    "usage: troupe COMMAND ARGS...\n"
    "\n"
    "  ls HOST                    list the devices of a node or simulator\n"
    "  echo HOST ADDR             print data as it arrives, one line each\n"
    "  cmd HOST ADDR VERB ARGS    send a command (e.g. vel 0.3 0 0.2)\n"
    "  req HOST ADDR VERB ARGS    send a request and print its reply\n"
    "  teleop HOST ADDR           drive a position2d device with the keyboard\n"
    "  help COMMAND               details and examples of a command\n"
    "\n"
    "HOST is HOST[:PORT] (port 6665 by default); ADDR is [ROBOT/]INTERFACE:INDEX,\n"
    "e.g. position2d:0 or r3/ranger:1. Other commands run the program troupe-COMMAND\n"
    "(installed tools such as troupe logmap or troupe mcl-eval).\n";

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
  fprintf(stderr, "troupe: unknown command '%s' (no program %s)\n\n%s", name.c_str(), program.c_str(), kUsage);
  return troupe::cli::kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    fputs(kUsage, stderr);
    return troupe::cli::kExitUsage;
  }
  std::string command = argv[1];
  std::vector<std::string> args(argv + 2, argv + argc);
  if (command == "-h" || command == "--help" || (command == "help" && args.empty())) {
    fputs(kUsage, stdout);
    return 0;
  }
  if (command == "help") {
    if (const char* text = troupe::cli::help_text(args[0])) {
      fputs(text, stdout);
      return 0;
    }
    return run_external(args[0], {"--help"});
  }
  for (const std::string& a : args) {
    if (a == "--help" || a == "-h") {
      if (const char* text = troupe::cli::help_text(command)) {
        fputs(text, stdout);
        return 0;
      }
    }
  }
  if (command == "ls") return troupe::cli::cmd_ls(args);
  if (command == "echo") return troupe::cli::cmd_echo(args);
  if (command == "cmd") return troupe::cli::cmd_send(args, troupe::wire::Kind::Command);
  if (command == "req") return troupe::cli::cmd_send(args, troupe::wire::Kind::Request);
  if (command == "teleop") return troupe::cli::cmd_teleop(args);
  return run_external(command, args);
}
