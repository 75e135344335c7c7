// Every troupe subcommand answers `troupe NAME --help` and `troupe help NAME`
// with exit status 0, its usage and an examples section, run through the
// troupe CLI as a user runs it (each program's folder on the PATH).
#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "cli_tools.h"
#include "tests/support/child_process.h"

namespace {

const std::string kTroupe = std::string(TROUPE_BINARY_DIR) + "/bin/troupe";

// The commands troupe runs itself, not through a troupe-NAME program.
const std::vector<std::string> kBuiltIn = {"ls", "echo", "cmd", "req", "teleop"};

struct Result {
  int rc = -1;
  std::string out, err;
};

/// Runs troupe with `args` (shell words) and the tools' folders first on the PATH.
Result troupe(const std::string& args) {
  std::string path;
  for (const CliTool& t : kCliTools) path += std::string(t.dir) + ":";
  const std::string command = "PATH='" + path + "'\"$PATH\" " + kTroupe + " " + args + " </dev/null";
  troupe::testing::ProgramResult r = troupe::testing::run_to_end({"/bin/sh", "-c", command}, 60000);
  return {r.status, r.out, r.err};
}

/// The lines after "examples:" up to the next blank line or the end.
std::vector<std::string> examples(const std::string& text) {
  std::vector<std::string> out;
  size_t at = text.find("\nexamples:\n");
  if (at == std::string::npos) return out;
  std::istringstream in(text.substr(at + 11));
  std::string line;
  while (std::getline(in, line) && !line.empty()) out.push_back(line);
  return out;
}

/// A help text: usage first, then an examples section whose every line runs
/// `name` (as troupe NAME or troupe-NAME).
void expect_help(const Result& r, const std::string& name, const std::string& how) {
  SCOPED_TRACE(how);
  EXPECT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(r.out.rfind("usage: troupe", 0), 0u) << r.out;
  std::vector<std::string> lines = examples(r.out);
  EXPECT_FALSE(lines.empty()) << "no examples section:\n" << r.out;
  for (const std::string& line : lines) {
    bool runs_it = line.find("troupe " + name + " ") != std::string::npos ||
                   line.find("troupe-" + name + " ") != std::string::npos;
    EXPECT_TRUE(runs_it) << "an example that does not run " << name << ": " << line;
  }
}

TEST(CliHelp, TheCommandListNamesEveryCommandAndHasExamples) {
  for (const char* how : {"help", "--help", "-h"}) {
    Result r = troupe(how);
    EXPECT_EQ(r.rc, 0) << how;
    EXPECT_EQ(r.out.rfind("usage: troupe COMMAND", 0), 0u) << r.out;
    EXPECT_FALSE(examples(r.out).empty()) << r.out;
    for (const std::string& name : kBuiltIn)
      EXPECT_NE(r.out.find("\n  " + name + " "), std::string::npos) << name;
    for (const CliTool& t : kCliTools) {
      EXPECT_NE(r.out.find("\n  " + std::string(t.name) + " "), std::string::npos) << t.name;
    }
  }
}

TEST(CliHelp, EveryBuiltInCommandHasHelpWithExamples) {
  for (const std::string& name : kBuiltIn) {
    expect_help(troupe(name + " --help"), name, name + " --help");
    expect_help(troupe("help " + name), name, "help " + name);
    // --help wins wherever it is, before any connection is tried.
    expect_help(troupe(name + " no-such-host.invalid --help"), name, name + " HOST --help");
  }
}

TEST(CliHelp, EveryProgramRunAsACommandHasHelpWithExamples) {
  ASSERT_GT(std::size(kCliTools), 0u);
  for (const CliTool& t : kCliTools) {
    const std::string name = t.name;
    expect_help(troupe(name + " --help"), name, name + " --help");
    expect_help(troupe("help " + name), name, "help " + name);
  }
}

TEST(CliHelp, AnUnknownCommandIsOneLineAndPointsAtHelp) {
  Result r = troupe("frobnicate --help");
  EXPECT_EQ(r.rc, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, "troupe: unknown command 'frobnicate' (no program troupe-frobnicate; see: troupe help)\n");
}

}  // namespace
