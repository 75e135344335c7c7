// robocup_match_bench: how fast a RoboCup match runs, as simulated seconds
// per CPU second of the one thread that steps it. The world file is run as
// it is (players, sensors, referee, the file's seed), flat out, `repeats`
// times from a fresh load; the table gives each run and the median. CPU
// time, not wall time, because the machine may be shared: time spent
// waiting for a processor is not the simulation's. The final score is
// printed so two builds can be seen to play the same match.
//
//   robocup_match_bench [--world FILE] [--seconds S] [--repeats N]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <vector>

#include "host-sim/robocup/game/simulation.h"
#include "tests/support/build_tree.h"
#include "wire/cli/args.h"

using namespace troupe::robocup;

namespace {

/// CPU time of the calling thread, s.
double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// One run's measurements: simulated s, CPU s and wall s of the stepping.
struct Run {
  double simulated_s = 0, cpu_s = 0, wall_s = 0;
  Score score;
};

bool run_once(const std::string& world, double seconds, Run& out) {
  WorldSpec spec;
  std::string error;
  if (!load_world_file(world, spec, error)) {
    fprintf(stderr, "robocup_match_bench: %s\n", error.c_str());
    return false;
  }
  auto sim = Simulation::create(std::move(spec), PluginLoader({troupe::testing::kPluginDir}), error);
  if (!sim) {
    fprintf(stderr, "robocup_match_bench: %s\n", error.c_str());
    return false;
  }
  const long steps = std::lround(seconds / sim->cycle_s());
  timespec w0{}, w1{};
  clock_gettime(CLOCK_MONOTONIC, &w0);
  const double c0 = thread_cpu_s();
  for (long i = 0; i < steps && sim->phase() != GamePhase::Stopped; ++i) sim->step();
  out.cpu_s = thread_cpu_s() - c0;
  clock_gettime(CLOCK_MONOTONIC, &w1);
  out.wall_s = double(w1.tv_sec - w0.tv_sec) + 1e-9 * double(w1.tv_nsec - w0.tv_nsec);
  out.simulated_s = sim->time_s();
  out.score = sim->score();
  return true;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  std::string world = TROUPE_SOURCE_DIR "/examples/robocup/match.world";
  double seconds = 60;
  int repeats = 5;
  auto app = troupe::cli::make_app(
      "robocup_match_bench",
      {"robocup_match_bench [--world FILE] [--seconds S] [--repeats N]",
       "A RoboCup match flat out: simulated seconds per CPU second, each run and the median.\n",
       {"robocup_match_bench --seconds 60 --repeats 5"}});
  app->add_option("--world", world, "the match (default: examples/robocup/match.world)")->type_name("FILE");
  app->add_option("--seconds", seconds, "simulated time per run, s (default 60)")
      ->type_name("S")
      ->check(troupe::cli::at_least(0.01));
  app->add_option("--repeats", repeats, "runs; the median is reported (default 5)")
      ->type_name("N")
      ->check(troupe::cli::at_least(1));
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;

  printf("%s, %.0f simulated s per run\n", world.c_str(), seconds);
  printf("%-6s %12s %10s %10s %16s %14s\n", "run", "simulated s", "CPU s", "wall s", "sim s / CPU s",
         "score b:y");
  std::vector<double> cpu, wall, speed;
  for (int i = 0; i < repeats; ++i) {
    Run r;
    if (!run_once(world, seconds, r)) return 1;
    cpu.push_back(r.cpu_s);
    wall.push_back(r.wall_s);
    speed.push_back(r.simulated_s / r.cpu_s);
    printf("%-6d %12.2f %10.3f %10.3f %16.1f %10d:%d\n", i + 1, r.simulated_s, r.cpu_s, r.wall_s,
           speed.back(), r.score.blue, r.score.yellow);
    fflush(stdout);
  }
  printf("%-6s %12s %10.3f %10.3f %16.1f\n", "median", "", median(cpu), median(wall), median(speed));
  return 0;
}
