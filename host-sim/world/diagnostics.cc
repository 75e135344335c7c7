#include "host-sim/world/diagnostics.h"

namespace troupe::world {

std::string SourceLoc::str() const {
  // Appended piece by piece: GCC 12 at -O3 warns falsely (-Wrestrict) about
  // "literal" + std::string temporaries.
  std::string s = file ? *file : std::string("<no file>");
  if (line > 0) s.append(":").append(std::to_string(line));
  return s;
}

std::string Diagnostic::str() const {
  std::string s = loc.str();
  s.append(severity == Severity::Error ? ": error: " : ": warning: ").append(message);
  return s;
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
