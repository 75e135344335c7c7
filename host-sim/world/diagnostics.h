// Warnings and errors found while loading a world, each with the file and
// line it is about. Loading never prints: the caller decides where the list
// goes (troupe-sim prints it, tests inspect it).
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace troupe::world {

/// Where a token, property or model came from. `file` is shared by every
/// location in the same file; line numbers start at 1 (0: no line).
struct SourceLoc {
  std::shared_ptr<const std::string> file;
  int line = 0;

  /// "path:line", or "path" without a line, or "<no file>".
  std::string str() const;
};

enum class Severity { Warning, Error };

struct Diagnostic {
  Severity severity = Severity::Error;
  SourceLoc loc;
  std::string message;

  /// "path:line: warning: message".
  std::string str() const;
};

class Diagnostics {
 public:
  void warn(const SourceLoc& loc, std::string message);
  void error(const SourceLoc& loc, std::string message);

  bool has_errors() const { return errors_ > 0; }
  size_t error_count() const { return errors_; }
  size_t warning_count() const { return items_.size() - errors_; }
  const std::vector<Diagnostic>& items() const { return items_; }
  /// Every diagnostic, one per line.
  std::string str() const;
  /// True when some diagnostic's message contains `text` (for tests and for
  /// callers that look for one kind of problem).
  bool contains(std::string_view text) const;

 private:
  std::vector<Diagnostic> items_;
  size_t errors_ = 0;
};

}  // namespace troupe::world
