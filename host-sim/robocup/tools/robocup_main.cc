// troupe-robocup: runs a RoboCup world (`troupe robocup` through the CLI).
// Without --script or --interactive it runs S simulated seconds (default:
// the referee's duration, else 60) as fast as it can and prints the
// referee's events and the final score. A script or standard input holds
// console commands (game/console.h): `start blue1 goalkeeper policy=block`,
// `run 10`, `score`, ... Serving a match over the wire, in real time and
// with the viewer, is troupe-sim's: `troupe-sim WORLD`. Exit status: 0 done,
// 1 a command failed, 2 the world could not be loaded.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "host-sim/plugin/plugin_loader.h"
#include "host-sim/robocup/game/console.h"
#include "runtime/log.h"
#include "wire/cli/args.h"

using namespace troupe::robocup;

int main(int argc, char** argv) {
  troupe::set_log_program("troupe-robocup");
  std::string world_file, script;
  double seconds = -1;
  uint64_t seed = 0;
  bool interactive = false, profile = false, quiet = false;
  std::vector<std::string> plugin_path;
  auto app = troupe::cli::make_app(
      "troupe-robocup",
      {"troupe-robocup WORLD [--seconds S] [--seed N] [--script FILE] [--interactive]\n"
       "                     [--plugin-path DIR]... [--profile] [--quiet]",
       "Runs a RoboCup F2000 world: the field, ball, robots and their plugins, and the\n"
       "referee. Without a script it runs as fast as it can and prints the referee's\n"
       "events and the final score. To serve a match over the wire (real time, the\n"
       "browser viewer, clients driving robots), run it with troupe-sim instead.\n",
       {"troupe-robocup examples/robocup/match.world --seconds 120 --seed 4",
        "troupe robocup examples/robocup/match.world --interactive   # then: run 5, score, quit"}});
  app->add_option("WORLD", world_file, "the world file")->required();
  app->add_option("--seconds", seconds, "simulated time to run, s (default: the referee's duration, else 60)")
      ->type_name("S")
      ->check(troupe::cli::at_least(0));
  auto* seed_given =
      app->add_option("--seed", seed, "seed of every random number in the run (default: the world's)")
          ->type_name("N")
          ->check(troupe::cli::at_least(0));
  app->add_option("--script", script,
                  "run console commands from FILE (run 10, start ROBOT PLUGIN, score, ...)")
      ->type_name("FILE");
  app->add_flag("--interactive", interactive, "run console commands typed on standard input");
  app->add_option("--plugin-path", plugin_path, "look for plugins in folder D first (repeatable)")
      ->type_name("D");
  app->add_flag("--profile", profile, "print the time spent in each phase of the cycle at the end");
  app->add_flag("--quiet", quiet, "no event lines, only the final score");
  // Serving a match is troupe-sim's: --serve (hidden) answers with the command that does it.
  bool serve = false;
  app->add_flag("--serve", serve)->group("");
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  if (serve)
    return troupe::cli::usage_error(*app,
                                    "to serve a match, run it with troupe-sim: troupe-sim " + world_file);
  WorldSpec spec;
  std::string error;
  if (!load_world_file(world_file, spec, error)) {
    fprintf(stderr, "troupe-robocup: %s\n", error.c_str());
    return 2;
  }
  if (seed_given->count() > 0) spec.seed = seed;
  PluginLoader loader(troupe::plugin::search_path(plugin_path, folder_of(world_file)));
  std::unique_ptr<Simulation> sim = Simulation::create(std::move(spec), std::move(loader), error);
  if (!sim) {
    fprintf(stderr, "troupe-robocup: %s\n", error.c_str());
    return 2;
  }
  if (!sim->problems().empty()) {
    fprintf(stderr, "troupe-robocup: running without %zu plugin(s), see above\n", sim->problems().size());
  }
  const auto wall0 = std::chrono::steady_clock::now();
  const double sim0 = sim->time_s();
  Console console(*sim, [quiet](const std::string& line) {
    if (!quiet) printf("%s\n", line.c_str());
  });
  int status = 0;
  if (!script.empty() || interactive) {
    std::ifstream file;
    std::istream* in = &std::cin;
    if (!script.empty()) {
      file.open(script);
      if (!file) {
        fprintf(stderr, "troupe-robocup: %s: cannot open\n", script.c_str());
        return 2;
      }
      in = &file;
    }
    std::string line;
    int number = 0;
    const std::string name = script.empty() ? "stdin" : script;
    while (!console.quit() && std::getline(*in, line)) {
      ++number;
      std::vector<Statement> commands;
      if (!parse_commands(line, name, commands, error)) {
        fprintf(stderr, "troupe-robocup: %s\n", error.c_str());
        status = 1;
        if (!interactive) break;
        continue;
      }
      for (Statement& c : commands) {
        c.line = number;
        if (!console.execute(c, error)) {
          fprintf(stderr, "troupe-robocup: %s\n", error.c_str());
          status = 1;
        }
      }
      if (status && !interactive) break;
      fflush(stdout);
    }
  } else {
    if (seconds < 0) seconds = sim->spec().referee.duration_s > 0 ? sim->spec().referee.duration_s : 60;
    const long steps = std::lround(seconds / sim->cycle_s());
    for (long i = 0; i < steps && sim->phase() != GamePhase::Stopped; ++i) console.run_steps(1);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const Score s = sim->score();
  printf("final: blue %d yellow %d after %.2f s simulated in %.2f s wall (%.1fx real time)\n", s.blue,
         s.yellow, sim->time_s(), wall, wall > 0 ? (sim->time_s() - sim0) / wall : 0.0);
  if (profile) printf("%s", sim->profile_table().c_str());
  return status;
}
