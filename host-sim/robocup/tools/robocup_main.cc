// troupe-robocup: runs a RoboCup world (`troupe robocup` through the CLI).
//
//   troupe-robocup WORLD [--seconds S] [--seed N] [--script FILE] [--interactive]
//                  [--plugin-path DIR]... [--profile] [--quiet]
//
// Without --script or --interactive it runs S simulated seconds (default:
// the referee's duration, else 60) as fast as it can and prints the
// referee's events and the final score. A script or standard input holds
// console commands (game/console.h): `start blue1 goalkeeper policy=block`,
// `run 10`, `score`, ... Serving a match over the wire, in real time and
// with the viewer, is troupe-sim's: `troupe-sim WORLD`. Exit status: 0 done,
// 1 a command failed, 2 the world could not be loaded.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>

#include "host-sim/plugin/plugin_loader.h"
#include "host-sim/robocup/game/console.h"
#include "runtime/log.h"

using namespace troupe::robocup;

namespace {

const char kUsage[] =
    "usage: troupe-robocup WORLD [--seconds S] [--seed N] [--script FILE] [--interactive]\n"
    "                     [--plugin-path DIR]... [--profile] [--quiet]\n";

const char kHelp[] =
    "\n"
    "Runs a RoboCup F2000 world: the field, ball, robots and their plugins, and the\n"
    "referee. Without a script it runs as fast as it can and prints the referee's\n"
    "events and the final score. To serve a match over the wire (real time, the\n"
    "browser viewer, clients driving robots), run it with troupe-sim instead.\n"
    "\n"
    "  --seconds S      simulated time to run, s (default: the referee's duration, else 60)\n"
    "  --seed N         seed of every random number in the run (default: the world's)\n"
    "  --script FILE    run console commands from FILE (run 10, start ROBOT PLUGIN, score, ...)\n"
    "  --interactive    run console commands typed on standard input\n"
    "  --plugin-path D  look for plugins in folder D first (repeatable)\n"
    "  --profile        print the mean time per cycle of each phase at the end\n"
    "  --quiet          no event lines, only the final score\n"
    "\n"
    "examples:\n"
    "  troupe-robocup examples/robocup/match.world --seconds 120 --seed 4\n"
    "  troupe robocup examples/robocup/match.world --interactive   # then: run 5, score, quit\n";

/// The short usage to stderr for a mistake; the whole help to stdout when asked.
void usage(bool asked = false) {
  fputs(kUsage, asked ? stdout : stderr);
  if (asked) fputs(kHelp, stdout);
}

struct Totals {
  CycleProfile sum;
  long cycles = 0;
  void add(const CycleProfile& p) {
    sum.players_s += p.players_s;
    sum.motion_s += p.motion_s;
    sum.kickers_s += p.kickers_s;
    sum.physics_s += p.physics_s;
    sum.referee_s += p.referee_s;
    sum.sensors_s += p.sensors_s;
    sum.total_s += p.total_s;
    ++cycles;
  }
  void print() const {
    if (cycles == 0) return;
    const std::pair<const char*, double> rows[] = {{"players", sum.players_s}, {"motion", sum.motion_s},
                                                   {"kickers", sum.kickers_s}, {"physics", sum.physics_s},
                                                   {"referee", sum.referee_s}, {"sensors", sum.sensors_s},
                                                   {"cycle", sum.total_s}};
    printf("%-8s %12s %8s\n", "phase", "mean us", "share");
    for (const auto& [name, s] : rows) {
      printf("%-8s %12.1f %7.1f%%\n", name, 1e6 * s / double(cycles),
             sum.total_s > 0 ? 100 * s / sum.total_s : 0);
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  troupe::set_log_program("troupe-robocup");
  std::string world_file, script;
  double seconds = -1;
  long seed = -1;
  bool interactive = false, profile = false, quiet = false;
  std::vector<std::string> plugin_path;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](const char* what) -> const char* {
      if (i + 1 >= argc) {
        fprintf(stderr, "troupe-robocup: %s needs %s\n", arg.c_str(), what);
        exit(2);
      }
      return argv[++i];
    };
    if (arg == "--seconds") {
      seconds = std::atof(value("seconds"));
    } else if (arg == "--seed") {
      seed = std::atol(value("a number"));
    } else if (arg == "--script") {
      script = value("a file");
    } else if (arg == "--plugin-path") {
      plugin_path.push_back(value("a folder"));
    } else if (arg == "--interactive") {
      interactive = true;
    } else if (arg == "--profile") {
      profile = true;
    } else if (arg == "--quiet") {
      quiet = true;
    } else if (arg == "--serve") {
      fprintf(stderr, "troupe-robocup: to serve a match, run it with troupe-sim: troupe-sim %s\n",
              world_file.empty() ? "WORLD" : world_file.c_str());
      return 2;
    } else if (arg == "-h" || arg == "--help") {
      usage(true);
      return 0;
    } else if (world_file.empty() && arg[0] != '-') {
      world_file = arg;
    } else {
      usage();
      return 2;
    }
  }
  if (world_file.empty()) {
    usage();
    return 2;
  }
  WorldSpec spec;
  std::string error;
  if (!load_world_file(world_file, spec, error)) {
    fprintf(stderr, "troupe-robocup: %s\n", error.c_str());
    return 2;
  }
  if (seed >= 0) spec.seed = uint64_t(seed);
  PluginLoader loader(troupe::plugin::search_path(plugin_path, folder_of(world_file)));
  std::unique_ptr<Simulation> sim = Simulation::create(std::move(spec), std::move(loader), error);
  if (!sim) {
    fprintf(stderr, "troupe-robocup: %s\n", error.c_str());
    return 2;
  }
  if (!sim->problems().empty()) {
    fprintf(stderr, "troupe-robocup: running without %zu plugin(s), see above\n", sim->problems().size());
  }
  Totals totals;
  const auto wall0 = std::chrono::steady_clock::now();
  const double sim0 = sim->time_s();
  Console console(*sim, [quiet](const std::string& line) {
    if (!quiet) printf("%s\n", line.c_str());
  });
  auto pace = [&] { totals.add(sim->profile()); };
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
    for (long i = 0; i < steps && sim->phase() != GamePhase::Stopped; ++i) {
      console.run_steps(1);
      pace();
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const Score s = sim->score();
  printf("final: blue %d yellow %d after %.2f s simulated in %.2f s wall (%.1fx real time)\n", s.blue,
         s.yellow, sim->time_s(), wall, wall > 0 ? (sim->time_s() - sim0) / wall : 0.0);
  if (profile) totals.print();
  return status;
}
