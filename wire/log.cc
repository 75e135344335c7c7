#include "wire/log.h"

#include <cstdarg>
#include <cstdio>
#include <cstring>

namespace troupe {
namespace {

LogLevel g_level = LogLevel::Info;
const char* g_program = "troupe";
const char* const kNames[] = {"error", "warn", "info", "debug"};

void vlog(LogLevel level, const char* fmt, va_list args) {
  if (level > g_level) return;
  // One fprintf-sized buffer so concurrent processes do not interleave
  // halves of lines on a shared terminal.
  char line[512];
  int n = snprintf(line, sizeof line, "%s: [%s] ", g_program, kNames[int(level)]);
  if (n < 0) return;
  size_t used = size_t(n) < sizeof line ? size_t(n) : sizeof line - 1;
  int m = vsnprintf(line + used, sizeof line - used, fmt, args);
  if (m < 0) return;
  used = used + size_t(m) < sizeof line - 1 ? used + size_t(m) : sizeof line - 2;
  line[used++] = '\n';
  fwrite(line, 1, used, stderr);
}

}  // namespace

void set_log_level(LogLevel level) { g_level = level; }
LogLevel log_level() { return g_level; }
void set_log_program(const char* name) { g_program = name; }

bool parse_log_level(const char* text, LogLevel& out) {
  for (int i = 0; i < 4; ++i) {
    if (strcmp(text, kNames[i]) == 0) {
      out = LogLevel(i);
      return true;
    }
  }
  return false;
}

#define TROUPE_DEFINE_LOG(fn, level) \
  void fn(const char* fmt, ...) {    \
    va_list args;                    \
    va_start(args, fmt);             \
    vlog(level, fmt, args);          \
    va_end(args);                    \
  }
TROUPE_DEFINE_LOG(log_error, LogLevel::Error)
TROUPE_DEFINE_LOG(log_warn, LogLevel::Warn)
TROUPE_DEFINE_LOG(log_info, LogLevel::Info)
TROUPE_DEFINE_LOG(log_debug, LogLevel::Debug)
#undef TROUPE_DEFINE_LOG

}  // namespace troupe
