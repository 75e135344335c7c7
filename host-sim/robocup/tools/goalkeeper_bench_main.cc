// troupe-goalkeeper-bench: the goalkeeper benchmark (`troupe
// goalkeeper-bench` through the CLI). Prints the table of goals per shots
// for every keeper policy and seed. Without --world it uses the standard
// world (bench/standard_world.cc).
#include <cstdio>

#include "host-sim/robocup/bench/goalkeeper_bench.h"
#include "runtime/log.h"
#include "wire/cli/args.h"

using namespace troupe::robocup;

namespace {

bool key_value(const std::string& s, std::pair<std::string, std::string>& out) {
  const size_t eq = s.find('=');
  if (eq == std::string::npos || eq == 0) return false;
  out = {s.substr(0, eq), s.substr(eq + 1)};
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  troupe::set_log_program("troupe-goalkeeper-bench");
  BenchSettings s;
  std::string world_file;
  bool quiet = false;
  auto app = troupe::cli::make_app(
      "troupe-goalkeeper-bench",
      {"troupe-goalkeeper-bench [--world FILE] [--shots N] [--seeds 1,2,3] [--policies a,b,...]\n"
       "       [--keeper ROBOT] [--striker ROBOT] [--keeper-plugin NAME] [--striker-plugin NAME]\n"
       "       [--keeper-option key=value]... [--striker-option key=value]...\n"
       "       [--plugin-path DIR]... [--timeout S] [--quiet]",
       "The goalkeeper benchmark: for every seed and keeper policy a striker takes the\n"
       "same seeded shots; prints goals, saves, misses and goals/shots per policy.\n",
       {"troupe-goalkeeper-bench --shots 100 --seeds 1,2,3",
        "troupe goalkeeper-bench --policies block,intercept --striker-plugin mystriker"}});
  app->add_option("--world", world_file, "robots `keeper` and `striker` (default: the standard world)")
      ->type_name("FILE");
  app->add_option("--shots", s.shots, "shots per policy and seed (default 20)")
      ->type_name("N")
      ->check(troupe::cli::between(1, 100000));
  app->add_option("--seeds", s.seeds, "seeds of the shots (default 1,2,3)")
      ->type_name("A,B,...")
      ->delimiter(',')
      ->check(troupe::cli::at_least(0));
  app->add_option("--policies", s.policies,
                  "keeper policies (default none,random,pattern,block,intercept,mixed)")
      ->type_name("A,B,...")
      ->delimiter(',');
  app->add_option("--keeper", s.keeper_robot, "the keeper's robot name in the world (default keeper)")
      ->type_name("ROBOT");
  app->add_option("--striker", s.striker_robot, "the striker's robot name in the world (default striker)")
      ->type_name("ROBOT");
  app->add_option("--keeper-plugin", s.keeper_plugin, "the keeper's player plugin (default goalkeeper)")
      ->type_name("NAME");
  app->add_option("--striker-plugin", s.striker_plugin, "the striker's player plugin (default striker)")
      ->type_name("NAME");
  std::vector<std::string> keeper_options, striker_options;
  app->add_option("--keeper-option", keeper_options, "one more keeper plugin option (repeatable)")
      ->type_name("K=V");
  app->add_option("--striker-option", striker_options, "one more striker plugin option (repeatable)")
      ->type_name("K=V");
  app->add_option("--plugin-path", s.plugin_path, "look for plugins in DIR first (repeatable)")
      ->type_name("DIR");
  app->add_option("--timeout", s.shot_timeout_s, "a shot not decided by then is over, s (default 6)")
      ->type_name("S")
      ->check(troupe::cli::above(0));
  app->add_flag("--quiet", quiet, "no progress on stderr");
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  for (auto [texts, options] :
       {std::pair{&keeper_options, &s.keeper_options}, std::pair{&striker_options, &s.striker_options}}) {
    for (const std::string& text : *texts) {
      std::pair<std::string, std::string> kv;
      if (!key_value(text, kv))
        return troupe::cli::usage_error(*app, "a plugin option is KEY=VALUE, not '" + text + "'");
      options->push_back(kv);
    }
  }
  if (s.seeds.empty() || s.policies.empty())
    return troupe::cli::usage_error(*app, "--seeds and --policies need a value");

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
