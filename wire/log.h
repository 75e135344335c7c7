// Log lines to stderr, filtered by level. printf-style so that a board build
// pulls in no stream library.
#pragma once

#include <cstdint>

namespace troupe {

enum class LogLevel { Error = 0, Warn = 1, Info = 2, Debug = 3 };

void set_log_level(LogLevel level);
LogLevel log_level();
/// Names every line, e.g. "troupe-node".
void set_log_program(const char* name);
/// Parses "error", "warn", "info", "debug"; returns false for anything else.
bool parse_log_level(const char* text, LogLevel& out);

void log_error(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
void log_warn(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
void log_info(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
void log_debug(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

/// For a message anyone can make a program repeat at will (a refused
/// input): counts one more in `count` and says whether to log this one,
/// the 1st, 2nd, 4th, 8th, ..., so a flood writes a few dozen lines.
inline bool log_this_one(uint64_t& count) {
  ++count;
  return (count & (count - 1)) == 0;
}

}  // namespace troupe
