// The command line of troupe-node: a flag parser small enough for a board
// binary (a few hundred bytes; the host tools use CLI11, wire/cli/args.h).
#pragma once

#include <cstddef>

namespace troupe {

/// A flag. By default it takes a value ("--port N"): `*value` points at the
/// word after it once parsed, and stays as it was when the flag is not
/// given; given twice, the last one counts.
///  - A switch ("--print-config") has `value == nullptr`: `*count` says
///    whether it was given.
///  - A repeatable flag ("--set A --set B") has `capacity` > 1: `value`
///    points at that many words, filled in command-line order, and `*count`
///    says how many; more is a mistake.
struct Flag {
  const char* name;
  const char** value;
  size_t* count = nullptr;
  size_t capacity = 1;
};

/// What a program's command line takes: its flags, one positional word
/// (`*positional`, required), and the help text, which starts with
/// "usage:" and ends with its examples.
struct CommandLine {
  const char* program;
  const char* usage;
  const Flag* flags;
  size_t flag_count;
  const char** positional;
};

/// Parses argv. -1: go on. 0: -h/--help printed the usage on stdout.
/// 2: a mistake, printed as "program: what" and the usage on stderr.
int parse_command_line(const CommandLine& line, int argc, char** argv);

}  // namespace troupe
