#include "tests/cli/help_checks.h"

#include <gtest/gtest.h>

#include <sstream>

#include "tests/support/child_process.h"

namespace troupe::testing {
namespace {

/// The lines after the line `heading` (and the blank lines right after it)
/// up to the next blank line or the end.
std::vector<std::string> section(const std::string& text, const std::string& heading) {
  std::vector<std::string> out;
  size_t at = ("\n" + text).find("\n" + heading + "\n");
  if (at == std::string::npos) return out;
  std::istringstream in(text.substr(at + heading.size() + 1));
  std::string line;
  while (std::getline(in, line) && line.empty()) {
  }
  do {
    if (line.empty()) break;
    out.push_back(line);
  } while (std::getline(in, line));
  return out;
}

/// "  NAME SYNOPSIS   summary" -> NAME.
std::string command_name(const std::string& line) {
  size_t begin = line.find_first_not_of(' ');
  if (begin == std::string::npos) return "";
  return line.substr(begin, line.find(' ', begin) - begin);
}

}  // namespace

CommandList listed_commands(const std::string& help_output) {
  CommandList list;
  for (const std::string& line : section(help_output, "usage: troupe COMMAND ARGS...")) {
    std::string name = command_name(line);
    if (name != "help") list.built_in.push_back(name);
  }
  for (const std::string& line :
       section(help_output, "programs run as troupe-COMMAND (next to troupe, else on the PATH):")) {
    list.programs.push_back(command_name(line));
  }
  return list;
}

TroupeRun run_troupe(const std::string& troupe, const std::string& args, const std::string& path) {
  const std::string command = "PATH='" + path + "' '" + troupe + "' " + args + " </dev/null";
  ProgramResult r = run_to_end({"/bin/sh", "-c", command}, 60000);
  return {r.status, r.out, r.err};
}

void expect_help(const TroupeRun& r, const std::string& name, const std::string& how) {
  SCOPED_TRACE(how);
  EXPECT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(r.out.rfind("usage: troupe", 0), 0u) << r.out;
  std::vector<std::string> lines = section(r.out, "examples:");
  EXPECT_FALSE(lines.empty()) << "no examples section:\n" << r.out;
  for (const std::string& line : lines) {
    bool runs_it = line.find("troupe " + name + " ") != std::string::npos ||
                   line.find("troupe-" + name + " ") != std::string::npos;
    EXPECT_TRUE(runs_it) << "an example that does not run " << name << ": " << line;
  }
}

void expect_every_listed_command_has_help(const std::string& troupe) {
  TroupeRun list = run_troupe(troupe, "help");
  ASSERT_EQ(list.rc, 0) << list.err;
  CommandList commands = listed_commands(list.out);
  ASSERT_FALSE(commands.built_in.empty()) << list.out;
  ASSERT_FALSE(commands.programs.empty()) << list.out;
  for (const auto* names : {&commands.built_in, &commands.programs}) {
    for (const std::string& name : *names) {
      expect_help(run_troupe(troupe, name + " --help"), name, name + " --help");
      expect_help(run_troupe(troupe, "help " + name), name, "help " + name);
    }
  }
}

}  // namespace troupe::testing
