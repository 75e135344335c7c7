// Every attack of the suite (tests/attack) against every program it applies
// to, with volumes `scale` times the tests', printed as a table: what was
// thrown and how much, whether the target survived, what got through, and
// its memory and descriptors before and after.
//
//   bench_attack [--bin DIR] [SCALE] [NAME...]
//
// SCALE defaults to 20; NAMEs pick attacks by name; --bin attacks the
// programs of another build (its bin/ folder), e.g. an older one.
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "tests/attack/attacks.h"

using namespace troupe::attack;

namespace {

std::string usage_cell(bool has, long before, long after) {
  if (!has || before < 0 || after < 0) return "-";
  return std::to_string(before) + " / " + std::to_string(after);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 2 && std::string(argv[1]) == "--bin") {
    set_program_dir(argv[2]);
    argc -= 2;
    argv += 2;
  }
  const int scale = argc > 1 ? std::max(1, std::atoi(argv[1])) : 20;
  // Thousands of connections at once: as many descriptors as allowed.
  rlimit files{};
  if (getrlimit(RLIMIT_NOFILE, &files) == 0) {
    files.rlim_cur = files.rlim_max;
    setrlimit(RLIMIT_NOFILE, &files);
  }
  std::printf(
      "| attack | target | volume | survived | let in | served after | RSS before / after (KiB) | fds before "
      "/ after | time (s) |\n");
  std::printf("|---|---|---:|---|---:|---|---:|---:|---:|\n");
  int failures = 0;
  for (const Attack& a : attacks()) {
    bool wanted = argc <= 2;
    for (int i = 2; i < argc; ++i) wanted = wanted || a.name == std::string(argv[i]);
    if (!wanted) continue;
    for (TargetKind k : a.targets) {
      const auto start = std::chrono::steady_clock::now();
      std::string error;
      const Outcome o = run_attack(a, k, scale, error);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (!error.empty()) {
        std::printf("| %s | %s | could not start: %s |\n", a.name, target_name(k), error.c_str());
        ++failures;
        continue;
      }
      std::printf("| %s | %s | %llu %s | %s | %llu | %s | %s | %s | %.1f |\n", a.name, target_name(k),
                  static_cast<unsigned long long>(o.volume), o.unit.c_str(), o.survived ? "yes" : "**no**",
                  static_cast<unsigned long long>(o.let_in), o.served ? "yes" : "**no**",
                  usage_cell(o.has_usage, o.before.rss_kib, o.after.rss_kib).c_str(),
                  usage_cell(o.has_usage, o.before.fds, o.after.fds).c_str(), seconds);
      std::fflush(stdout);
      if (!o.survived || o.let_in > 0 || !o.served) {
        ++failures;
        std::fprintf(stderr, "%s on %s: %s%s%s\n", a.name, target_name(k), o.first_let_in.c_str(),
                     o.served ? "" : "; not served: ", o.served ? "" : o.why_not_served.c_str());
      }
    }
  }
  return failures == 0 ? 0 : 1;
}
