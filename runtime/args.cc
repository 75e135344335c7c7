#include "runtime/args.h"

#include <cstdio>
#include <cstring>

namespace troupe {
namespace {

int mistake(const CommandLine& line, const char* what, const char* arg) {
  fprintf(stderr, "%s: %s '%s'\n%s", line.program, what, arg, line.usage);
  return 2;
}

}  // namespace

int parse_command_line(const CommandLine& line, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const char* a = argv[i];
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      fputs(line.usage, stdout);
      return 0;
    }
  }
  for (int i = 1; i < argc; ++i) {
    const char* a = argv[i];
    const Flag* flag = nullptr;
    for (size_t f = 0; f < line.flag_count; ++f) {
      if (strcmp(a, line.flags[f].name) == 0) flag = &line.flags[f];
    }
    if (flag != nullptr && flag->value == nullptr) {
      *flag->count = 1;
    } else if (flag != nullptr) {
      if (i + 1 >= argc) return mistake(line, "a value is missing after", a);
      size_t at = 0;
      if (flag->capacity > 1) {
        if (*flag->count == flag->capacity) return mistake(line, "too many of", a);
        at = (*flag->count)++;
      }
      flag->value[at] = argv[++i];
    } else if (a[0] == '-' || *line.positional != nullptr) {
      return mistake(line, "unexpected argument", a);
    } else {
      *line.positional = a;
    }
  }
  if (*line.positional == nullptr) {
    fputs(line.usage, stderr);
    return 2;
  }
  return -1;
}

}  // namespace troupe
