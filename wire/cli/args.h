// Command lines of the host tools, on CLI11, in one house style
// (wire/cli/README.md has the pattern every program follows).
#pragma once

#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <vector>

#include "wire/noise/client_keys.h"

namespace troupe::cli {

/// Exit codes of every tool: 0 ok, 1 a runtime failure (no host, no device,
/// refused), 2 bad usage.
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

/// What a program's help shows around its options. `usage` follows
/// "usage: " (the program's name and its arguments), `about` is the
/// paragraph under it (whole lines, each ending in '\n'), and every example
/// is a command line that runs the program.
struct Help {
  std::string usage;
  std::string about;
  std::vector<std::string> examples;
};

/// A command line in the house style. `name` is what the user types to run
/// it ("troupe record", "troupe-view"): it starts the one-line errors.
/// `-h`/`--help` anywhere prints the help; options are listed from their
/// definitions, so each one's text (with its unit) is written once, where it
/// is added: `app.add_option("--duration", s, "stop after S seconds")->type_name("S")`.
/// Options put in a group (`->group("hardware in the loop")`) follow under
/// that heading; options in group "" are hidden.
std::unique_ptr<CLI::App> make_app(const std::string& name, Help help);

/// Parses the arguments after the program's name. Returns -1 when the
/// program goes on; otherwise the exit status, after printing: 0 after the
/// help (on stdout), kExitUsage after one line on stderr,
/// "NAME: what is wrong (see: NAME --help)".
int parse(CLI::App& app, int argc, const char* const* argv);
int parse(CLI::App& app, const std::vector<std::string>& args);

/// Prints "NAME: message (see: NAME --help)" on stderr for an error found
/// after parsing (a bad address, say), and returns kExitUsage.
int usage_error(const CLI::App& app, const std::string& message);

/// Checks of a number with one-line messages ("needs a number >= 1, not '0'"):
/// at least `min`, above it (a duration > 0), at most `max`, from `min` to
/// `max` (one message for both bounds); combine with &.
CLI::Validator at_least(double min);
CLI::Validator above(double min);
CLI::Validator at_most(double max);
CLI::Validator between(double min, double max);

/// `--log-level LEVEL`, one of error, warn, info, debug: sets the program's
/// log level (wire/log.h) when given.
CLI::Option* add_log_level(CLI::App& app);

/// `--identity FILE` and `--node-key KEY`: a secure session with the node
/// (wire/noise/client_keys.h turns them into the session's transport).
void add_secure_session(CLI::App& app, wire::noise::ClientKeys& keys);

/// A port number 0..65535 (0: any free port, where the program says so).
CLI::Option* add_port(CLI::App& app, const std::string& flag, uint16_t& port, const std::string& what);

}  // namespace troupe::cli
