// What every `troupe` command's help must be, checked through the troupe
// CLI as a user runs it: the build tree's (tests/cli) and an installed
// tree's (tests/install).
#pragma once

#include <string>
#include <vector>

namespace troupe::testing {

/// The commands `troupe help` lists: the built-in ones (run by troupe
/// itself) and the programs (run as troupe-NAME).
struct CommandList {
  std::vector<std::string> built_in, programs;
};
CommandList listed_commands(const std::string& help_output);

/// Runs `troupe` (a path) with `args` (shell words) and stdin from
/// /dev/null. `path` is the PATH it runs with: what it finds there, it finds
/// beside itself or nowhere.
struct TroupeRun {
  int rc = -1;
  std::string out, err;
};
TroupeRun run_troupe(const std::string& troupe, const std::string& args, const std::string& path = "/usr/bin:/bin");

/// Checks (gtest failures) that `r` is the help of command `name`: exit 0,
/// "usage: troupe" first, and an examples section whose every line runs it
/// (as `troupe NAME` or `troupe-NAME`).
void expect_help(const TroupeRun& r, const std::string& name, const std::string& how);

/// Checks every command `troupe help` lists answers `troupe NAME --help`
/// and `troupe help NAME` with its help.
void expect_every_listed_command_has_help(const std::string& troupe);

}  // namespace troupe::testing
