// troupe-goalkeeper-bench: the goalkeeper benchmark (`troupe
// goalkeeper-bench` through the CLI). Prints the table of goals per shots
// for every keeper policy and seed.
//
//   troupe-goalkeeper-bench [--world FILE] [--shots N] [--seeds 1,2,3]
//       [--policies none,random,pattern,block,intercept,mixed]
//       [--keeper ROBOT] [--striker ROBOT] [--keeper-plugin NAME] [--striker-plugin NAME]
//       [--keeper-option key=value]... [--striker-option key=value]...
//       [--plugin-path DIR]... [--timeout S] [--quiet]
//
// Without --world it uses the standard world (bench/standard_world.cc).
#include <cstdio>
#include <cstring>

#include "host-sim/robocup/bench/goalkeeper_bench.h"
#include "runtime/log.h"

using namespace troupe::robocup;

namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= s.size()) {
    size_t comma = s.find(',', start);
    if (comma == std::string::npos) comma = s.size();
    if (comma > start) out.push_back(s.substr(start, comma - start));
    start = comma + 1;
  }
  return out;
}

bool key_value(const std::string& s, std::pair<std::string, std::string>& out) {
  const size_t eq = s.find('=');
  if (eq == std::string::npos || eq == 0) return false;
  out = {s.substr(0, eq), s.substr(eq + 1)};
  return true;
}

const char kUsage[] =
    "usage: troupe-goalkeeper-bench [--world FILE] [--shots N] [--seeds 1,2,3] [--policies a,b,...]\n"
    "       [--keeper ROBOT] [--striker ROBOT] [--keeper-plugin NAME] [--striker-plugin NAME]\n"
    "       [--keeper-option key=value]... [--striker-option key=value]...\n"
    "       [--plugin-path DIR]... [--timeout S] [--quiet]\n";

const char kHelp[] =
    "\n"
    "The goalkeeper benchmark: for every seed and keeper policy a striker takes the\n"
    "same seeded shots; prints goals, saves, misses and goals/shots per policy.\n"
    "\n"
    "  --world FILE          robots `keeper` and `striker` (default: the standard world)\n"
    "  --shots N             shots per policy and seed (default 20)\n"
    "  --seeds A,B,...       seeds of the shots (default 1,2,3)\n"
    "  --policies A,B,...    keeper policies (default none,random,pattern,block,intercept,mixed)\n"
    "  --keeper/--striker ROBOT           robot names in the world\n"
    "  --keeper-plugin/--striker-plugin NAME   player plugins (default goalkeeper, striker)\n"
    "  --keeper-option/--striker-option K=V    more plugin options (repeatable)\n"
    "  --plugin-path DIR     look for plugins in DIR first (repeatable)\n"
    "  --timeout S           a shot not decided by then is over, s (default 6)\n"
    "  --quiet               no progress on stderr\n"
    "\n"
    "examples:\n"
    "  troupe-goalkeeper-bench --shots 100 --seeds 1,2,3\n"
    "  troupe goalkeeper-bench --policies block,intercept --striker-plugin mystriker\n";

/// The short usage to stderr for a mistake (exit 2); the whole help to
/// stdout when asked (exit 0).
int usage(bool asked = false) {
  fputs(kUsage, asked ? stdout : stderr);
  if (asked) fputs(kHelp, stdout);
  return asked ? 0 : 2;
}

}  // namespace

int main(int argc, char** argv) {
  troupe::set_log_program("troupe-goalkeeper-bench");
  BenchSettings s;
  std::string world_file;
  bool quiet = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--quiet") {
      quiet = true;
      continue;
    }
    if (arg == "-h" || arg == "--help") return usage(true);
    if (i + 1 >= argc) return usage();
    const std::string v = argv[++i];
    std::pair<std::string, std::string> kv;
    if (arg == "--world") {
      world_file = v;
    } else if (arg == "--shots") {
      s.shots = std::atoi(v.c_str());
      if (s.shots <= 0 || s.shots > 100000) return usage();
    } else if (arg == "--seeds") {
      s.seeds.clear();
      for (const std::string& x : split(v)) s.seeds.push_back(std::strtoull(x.c_str(), nullptr, 10));
      if (s.seeds.empty()) return usage();
    } else if (arg == "--policies") {
      s.policies = split(v);
      if (s.policies.empty()) return usage();
    } else if (arg == "--keeper") {
      s.keeper_robot = v;
    } else if (arg == "--striker") {
      s.striker_robot = v;
    } else if (arg == "--keeper-plugin") {
      s.keeper_plugin = v;
    } else if (arg == "--striker-plugin") {
      s.striker_plugin = v;
    } else if (arg == "--keeper-option" && key_value(v, kv)) {
      s.keeper_options.push_back(kv);
    } else if (arg == "--striker-option" && key_value(v, kv)) {
      s.striker_options.push_back(kv);
    } else if (arg == "--plugin-path") {
      s.plugin_path.push_back(v);
    } else if (arg == "--timeout") {
      s.shot_timeout_s = std::atof(v.c_str());
      if (!(s.shot_timeout_s > 0)) return usage();
    } else {
      return usage();
    }
  }
  WorldSpec world;
  std::string error;
  const bool ok = world_file.empty() ? parse_world_text(standard_bench_world(), "standard-bench.world", world, error)
                                     : load_world_file(world_file, world, error);
  if (!ok) {
    fprintf(stderr, "troupe-goalkeeper-bench: %s\n", error.c_str());
    return 2;
  }
  std::vector<BenchCell> cells;
  if (!run_goalkeeper_bench(world, s, cells, error, quiet ? nullptr : stderr)) {
    fprintf(stderr, "troupe-goalkeeper-bench: %s\n", error.c_str());
    return 1;
  }
  print_bench_table(cells, s, stdout);
  return 0;
}
