// The goalkeeper benchmark: a striker takes N shots from seeded positions
// against a goalkeeper, once per keeper policy and seed; the result is the
// table of goals per shots. Every policy faces the same shots for a seed.
// README.md ("Goalkeeper benchmark") says how to run it against your own
// striker.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "host-sim/robocup/game/world_spec.h"

namespace troupe::robocup {

struct BenchSettings {
  int shots = 20;
  std::vector<uint64_t> seeds = {1, 2, 3};
  std::vector<std::string> policies = {"none", "random", "pattern", "block", "intercept", "mixed"};
  /// Robots of the world that keep and shoot, and the player plugins that
  /// drive them (the keeper's gets policy=...; the striker's aim_y=...).
  std::string keeper_robot = "keeper", striker_robot = "striker";
  std::string keeper_plugin = "goalkeeper", striker_plugin = "striker";
  /// More key=value options for the two players.
  std::vector<std::pair<std::string, std::string>> keeper_options, striker_options;
  /// Shots start this far from the goal's centre, m, within this angle of
  /// the goal's axis, rad, aimed within this distance of the goal's centre
  /// line, m.
  double min_distance = 2.0, max_distance = 4.0, max_angle = 0.87, max_aim = 0.8;
  /// A shot not decided by then is over, s.
  double shot_timeout_s = 6;
  /// Extra plugin folders.
  std::vector<std::string> plugin_path;
};

/// Results of one policy and seed.
struct BenchCell {
  std::string policy;
  uint64_t seed = 0;
  int shots = 0, goals = 0;
  /// No goal, the keeper touched the ball / did not.
  int saves = 0, misses = 0;
  /// The striker never got its shot off in time.
  int no_kick = 0;
};

/// Where each shot of a seed starts and aims (the same for every policy).
struct ShotSetup {
  /// World, m.
  Vec2 ball;
  /// m from the goal's centre along the goal line.
  double aim_y = 0;
};
std::vector<ShotSetup> shot_setups(const BenchSettings& s, const FieldSpec& field, uint64_t seed);

/// Runs the benchmark; `progress` (may be null) gets a line per finished
/// cell. False with `error` when the world or a player cannot be set up.
bool run_goalkeeper_bench(const WorldSpec& world, const BenchSettings& settings, std::vector<BenchCell>& out,
                          std::string& error, FILE* progress = nullptr);

void print_bench_table(const std::vector<BenchCell>& cells, const BenchSettings& settings, FILE* to);

/// The standard benchmark world: the 2001 field, an omni goalkeeper for
/// blue and a Pioneer striker for yellow, defined inline.
const char* standard_bench_world();

}  // namespace troupe::robocup
