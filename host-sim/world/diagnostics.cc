#include "host-sim/world/diagnostics.h"

namespace troupe::world {

std::string SourceLoc::str() const {
  std::string s = file ? *file : std::string("<no file>");
  if (line > 0) s += ":" + std::to_string(line);
  return s;
}

std::string Diagnostic::str() const {
  return loc.str() + (severity == Severity::Error ? ": error: " : ": warning: ") + message;
}

void Diagnostics::warn(const SourceLoc& loc, std::string message) {
  items_.push_back({Severity::Warning, loc, std::move(message)});
}

void Diagnostics::error(const SourceLoc& loc, std::string message) {
  items_.push_back({Severity::Error, loc, std::move(message)});
  ++errors_;
}

std::string Diagnostics::str() const {
  std::string out;
  for (const Diagnostic& d : items_) out += d.str() + "\n";
  return out;
}

bool Diagnostics::contains(std::string_view text) const {
  for (const Diagnostic& d : items_) {
    if (d.message.find(text) != std::string::npos) return true;
  }
  return false;
}

}  // namespace troupe::world
