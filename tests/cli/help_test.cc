// Every command `troupe help` lists runs through `troupe NAME` from the
// build tree (bin/, nothing else on the PATH), and answers `troupe NAME
// --help` and `troupe help NAME` with its usage and an examples section.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "tests/cli/help_checks.h"

namespace troupe::testing {
namespace {

const std::string kTroupe = std::string(TROUPE_BINARY_DIR) + "/bin/troupe";

TEST(CliHelp, TheCommandListNamesCommandsAndHasExamples) {
  for (const char* how : {"help", "--help", "-h"}) {
    TroupeRun r = run_troupe(kTroupe, how);
    EXPECT_EQ(r.rc, 0) << how;
    EXPECT_EQ(r.out.rfind("usage: troupe COMMAND", 0), 0u) << r.out;
    EXPECT_NE(r.out.find("\nexamples:\n  troupe "), std::string::npos) << r.out;
    CommandList list = listed_commands(r.out);
    EXPECT_EQ(list.built_in, (std::vector<std::string>{"ls", "echo", "cmd", "req", "teleop", "keygen"})) << r.out;
    // The programs of this build, each run as troupe-NAME.
    for (const char* program : {"record", "play", "sim", "node", "view", "emulate-p2os", "emulate-sick",
                                "emulate-odrive"}) {
      EXPECT_NE(std::find(list.programs.begin(), list.programs.end(), program), list.programs.end()) << program;
    }
  }
}

TEST(CliHelp, EveryListedCommandRunsAndHasHelpWithExamples) { expect_every_listed_command_has_help(kTroupe); }

TEST(CliHelp, HelpWinsWhereverItIsBeforeAnyConnection) {
  for (const std::string name : {"ls", "echo", "cmd", "req", "teleop", "keygen"}) {
    expect_help(run_troupe(kTroupe, name + " no-such-host.invalid --help"), name, name + " HOST --help");
  }
}

TEST(CliHelp, AnUnknownCommandIsOneLineAndPointsAtHelp) {
  TroupeRun r = run_troupe(kTroupe, "frobnicate --help");
  EXPECT_EQ(r.rc, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, "troupe: unknown command 'frobnicate' (no program troupe-frobnicate; see: troupe help)\n");
}

}  // namespace
}  // namespace troupe::testing
