// The text format of RoboCup world and robot files (README.md, "File
// format"): one statement per line,
//
//   keyword [word ...] [key=value ...] [{ statement ... }]
//
// `#` starts a comment, "double quotes" hold spaces, a block in braces
// holds child statements, and `include "file"` inserts another file
// (relative to the including one). Every statement remembers its file and
// line so that whoever reads it can say where a problem is.
#pragma once

#include <string>
#include <vector>

#include "host-sim/robocup/api/options.h"

namespace troupe::robocup {

struct Statement {
  std::string keyword;
  /// Words after the keyword that are not key=value.
  std::vector<std::string> args;
  /// key=value pairs in the order written.
  std::vector<std::pair<std::string, std::string>> options;
  std::vector<Statement> children;
  std::string file;
  int line = 0;

  /// "file:line".
  std::string where() const { return file + ":" + std::to_string(line); }
  /// The options as an Options object (for typed reading).
  Options reader() const;
};

/// Parses `text`, naming it `file` in messages; `include`s are resolved
/// relative to the folder of `file`. False with "file:line: why".
bool parse_config_text(const std::string& text, const std::string& file, std::vector<Statement>& out,
                       std::string& error);
/// Reads and parses a file.
bool parse_config_file(const std::string& path, std::vector<Statement>& out, std::string& error);

/// The folder part of a path ("" for a bare file name).
std::string folder_of(const std::string& path);

}  // namespace troupe::robocup
