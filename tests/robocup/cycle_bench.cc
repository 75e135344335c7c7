// robocup_cycle_bench: what a RoboCup cycle costs, as a table. Each scene
// is run `repeats` times; the median wall time per cycle is compared with
// the baseline scene (the field with a rolling ball) of the same run.
//
//   robocup_cycle_bench [seconds per run, default 20] [repeats, default 5]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "host-sim/robocup/game/simulation.h"
#include "tests/support/build_tree.h"

using namespace troupe::robocup;

namespace {

const std::string kMatch = TROUPE_SOURCE_DIR "/examples/robocup/match.world";

struct Scene {
  const char* name;
  bool robots, players, sensors;
};

double run_once(const Scene& scene, double seconds) {
  WorldSpec spec;
  std::string error;
  if (!load_world_file(kMatch, spec, error)) {
    fprintf(stderr, "%s\n", error.c_str());
    exit(1);
  }
  if (!scene.robots) spec.robots.clear();
  for (RobotEntry& r : spec.robots) {
    r.has_player = r.has_player && scene.players;
    if (!scene.sensors) r.spec.sensors.clear();
  }
  spec.referee.duration_s = 0;
  auto sim = Simulation::create(std::move(spec), PluginLoader({troupe::testing::kPluginDir}), error);
  if (!sim) {
    fprintf(stderr, "%s\n", error.c_str());
    exit(1);
  }
  sim->place_ball({0, 0}, {3, 2});
  const long steps = std::lround(seconds / sim->cycle_s());
  const auto t0 = std::chrono::steady_clock::now();
  for (long i = 0; i < steps; ++i) sim->step();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / double(steps);
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 20;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 5;
  const Scene scenes[] = {{"field + ball (baseline)", false, false, false},
                          {"8 robots, no plugins", true, false, false},
                          {"8 robots + players", true, true, false},
                          {"8 robots + players + sensors", true, true, true}};
  printf("RoboCup cycle cost: %.0f simulated s per run, median of %d runs, 0.01 s cycles\n", seconds,
         repeats);
  printf("%-32s %14s %10s %14s\n", "scene", "us per cycle", "x baseline", "x real time");
  double baseline = 0;
  for (const Scene& s : scenes) {
    std::vector<double> t;
    for (int i = 0; i < repeats; ++i) t.push_back(run_once(s, seconds));
    std::sort(t.begin(), t.end());
    const double median = t[t.size() / 2];
    if (baseline == 0) baseline = median;
    printf("%-32s %14.1f %10.2f %14.0f\n", s.name, median * 1e6, median / baseline, 0.01 / median);
  }
  return 0;
}
