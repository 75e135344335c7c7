// mpi_scaling: how a divided troupe-sim scales. It runs the real program
// as users do, under mpirun at 1 and 2 ranks and alone (no mpirun: the
// baseline), on the scale rows' office worlds (sim_bench --write-scale),
// and prints tables: simulated seconds per wall second and per CPU second
// of the stepping (troupe-sim --profile's last line and its division table:
// loading the world is not counted), speed-up and efficiency against the
// baseline, then per step and rank what the ranks exchanged and where their
// time went, and the slowest rank's own work (CPU s outside MPI calls), a
// speed the shared machine's load does not change. A program of its own
// rather than a sim_bench row: its runs are whole troupe-sim processes
// under mpirun, not a World stepped in-process.
// Runs are alternated (every configuration once, then again) and medians
// reported, with the machine's load, which is shared.
//
//   mpi_scaling [strong] [weak] [huge] [--repeats N] [--sim-seconds S] [--dir DIR]
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/bench/sim/rows.h"
#include "tests/support/child_process.h"
#include "wire/cli/args.h"

namespace {

const std::string kSim = std::string(TROUPE_BINARY_DIR) + "/bin/troupe-sim";

// One configuration: a world of `robots` robots stepped by `ranks`
// processes under mpirun (0: one process without mpirun).
struct Config {
  int robots = 0;
  int ranks = 0;
};

// What one rank's line of the division table says (per step: bytes,
// messages; over the run: s).
struct RankRow {
  int robots = 0;
  double bytes_per_step = 0, messages_per_step = 0, exchanging_s = 0, waiting_s = 0, other_s = 0, cpu_s = 0,
         mpi_cpu_s = 0;
  // CPU s of the rank's own work: what it would take on a core of its own.
  double work_cpu_s() const { return cpu_s - mpi_cpu_s; }
};

// One run's figures: simulated s, wall s and CPU s (every rank) of the
// stepping, the slowest rank's own work (CPU s outside MPI), and the
// division's table when divided.
struct Run {
  double sim_s = 0, wall_s = 0, cpu_s = 0, slowest_work_s = 0, load = 0;
  std::vector<RankRow> ranks;
  double per_wall() const { return wall_s > 0 ? sim_s / wall_s : 0; }
  double per_cpu() const { return cpu_s > 0 ? sim_s / cpu_s : 0; }
  // Simulated s per CPU s of the slowest rank's work: the speed with a core
  // for each rank and no time to move bytes, which this shared machine's
  // load does not change.
  double per_work() const { return slowest_work_s > 0 ? sim_s / slowest_work_s : 0; }
};

double load_now() {
  double one = 0;
  std::ifstream("/proc/loadavg") >> one;
  return one;
}

// Reads troupe-sim --profile's stderr: the "run:" line and the rows of the
// division's table (after its "rank  robots" header). False when the run
// line is missing.
bool parse_profile(const std::string& err, bool divided, Run& run) {
  std::istringstream in(err);
  std::string line;
  bool in_table = false, have_run = false;
  unsigned long long steps = 0;
  while (std::getline(in, line)) {
    if (line.rfind("rank  robots", 0) == 0) {
      in_table = true;
      continue;
    }
    if (std::sscanf(line.c_str(), "run: %llu steps, %lf simulated s, %lf wall s, %lf CPU s", &steps,
                    &run.sim_s, &run.wall_s, &run.cpu_s) == 4) {
      have_run = true;
      in_table = false;
      continue;
    }
    if (!in_table) continue;
    int rank = 0;
    unsigned long long migrated = 0, map_builds = 0;
    double world_mb = 0;
    RankRow r;
    if (std::sscanf(line.c_str(), "%d %d %lf %lf %llu %lf %lf %lf %llu %lf %lf %lf", &rank, &r.robots,
                    &r.bytes_per_step, &r.messages_per_step, &migrated, &r.exchanging_s, &r.other_s,
                    &world_mb, &map_builds, &r.waiting_s, &r.cpu_s, &r.mpi_cpu_s) == 12) {
      run.ranks.push_back(r);
    } else {
      in_table = false;
    }
  }
  // A divided run's CPU is every rank's, not the leader's alone.
  run.slowest_work_s = run.cpu_s;
  if (divided && !run.ranks.empty()) {
    run.cpu_s = 0;
    run.slowest_work_s = 0;
    for (const RankRow& r : run.ranks) {
      run.cpu_s += r.cpu_s;
      run.slowest_work_s = std::max(run.slowest_work_s, r.work_cpu_s());
    }
  }
  return have_run && (!divided || !run.ranks.empty());
}

std::string world_path(const std::string& dir, int robots) {
  return (std::filesystem::path(dir) / ("office" + std::to_string(robots)) / "office.world").string();
}

bool run_once(const std::string& dir, const Config& c, double sim_seconds, Run& out) {
  std::vector<std::string> argv;
  if (c.ranks > 0) {
    // Not bound to cores: the machine is shared, the OS places the ranks.
    argv = {MPIEXEC, "--oversubscribe", "--bind-to", "none", "-np", std::to_string(c.ranks)};
  }
  const std::vector<std::string> sim = {kSim,
                                        world_path(dir, c.robots),
                                        "--no-serve",
                                        "--fast",
                                        "--quit-time",
                                        std::to_string(sim_seconds),
                                        "--profile",
                                        "--seed",
                                        "1"};
  argv.insert(argv.end(), sim.begin(), sim.end());
  out = Run{};
  out.load = load_now();
  const troupe::testing::ProgramResult r = troupe::testing::run_to_end(argv, 3600 * 1000);
  if (r.status != 0 || !parse_profile(r.err, c.ranks > 0, out)) {
    std::fprintf(stderr, "mpi_scaling: %s ended with status %d:\n%s\n", argv.front().c_str(), r.status,
                 r.err.c_str());
    return false;
  }
  return true;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

std::string label(const Config& c) {
  return c.ranks == 0 ? "1 process (no mpirun)"
                      : std::to_string(c.ranks) + (c.ranks == 1 ? " rank" : " ranks");
}

// Runs every configuration `repeats` times, alternated; the runs of each.
bool measure(const std::string& dir, const std::vector<Config>& configs, int repeats, double sim_seconds,
             std::vector<std::vector<Run>>& runs) {
  runs.assign(configs.size(), {});
  for (int k = 0; k < repeats; ++k) {
    for (size_t i = 0; i < configs.size(); ++i) {
      Run r;
      if (!run_once(dir, configs[i], sim_seconds, r)) return false;
      std::fprintf(
          stderr, "  %d robots, %s: %.2f sim s/wall s, %.2f sim s/CPU s, %.2f sim s/work s, load %.1f\n",
          configs[i].robots, label(configs[i]).c_str(), r.per_wall(), r.per_cpu(), r.per_work(), r.load);
      runs[i].push_back(r);
    }
  }
  return true;
}

// The run whose wall-clock speed is the median of its configuration's: its
// per-rank table is the one shown.
const Run& median_run(const std::vector<Run>& runs) {
  std::vector<size_t> order(runs.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return runs[a].per_wall() < runs[b].per_wall(); });
  return runs[order[order.size() / 2]];
}

// The table: one row per configuration; speed-up and efficiency against
// `base` (the configuration index), by wall clock and by the slowest rank's
// work; for weak scaling (work grows with the ranks) against robot-steps
// per s.
void print_table(const char* title, const std::vector<Config>& configs,
                 const std::vector<std::vector<Run>>& runs, size_t base, bool weak) {
  std::printf("\n%s\n", title);
  std::printf("%-22s %7s %11s %11s %11s %9s %9s %9s %5s %6s\n", "processes", "robots", "sim s/wall",
              "sim s/CPU", "sim s/work", "x wall", "x work", "eff work", "runs", "load");
  auto medians = [&](double (Run::*f)() const) {
    std::vector<double> out(configs.size());
    for (size_t i = 0; i < configs.size(); ++i) {
      std::vector<double> v;
      for (const Run& r : runs[i]) v.push_back((r.*f)());
      out[i] = median(v);
    }
    return out;
  };
  const std::vector<double> wall = medians(&Run::per_wall), cpu = medians(&Run::per_cpu),
                            work = medians(&Run::per_work);
  for (size_t i = 0; i < configs.size(); ++i) {
    std::vector<double> load;
    for (const Run& r : runs[i]) load.push_back(r.load);
    const int ranks = std::max(configs[i].ranks, 1);
    // Weak: robots stepped per s against the baseline's; strong: the same
    // world's speed.
    const double more = weak ? double(configs[i].robots) / configs[base].robots : 1.0;
    const double x_wall = wall[base] > 0 ? wall[i] * more / wall[base] : 0;
    const double x_work = work[base] > 0 ? work[i] * more / work[base] : 0;
    std::printf("%-22s %7d %11.2f %11.2f %11.2f %8.2fx %8.2fx %8.0f%% %5zu %6.1f\n",
                label(configs[i]).c_str(), configs[i].robots, wall[i], cpu[i], work[i], x_wall, x_work,
                100.0 * x_work / ranks, runs[i].size(), median(load));
  }
  std::printf("(medians; work: CPU s outside MPI of the slowest rank; x: %s against the first row)\n",
              weak ? "robot-steps per s" : "speed");
  std::printf("\nper step and rank (the median run of each divided configuration; s over the whole run)\n");
  std::printf("%-22s %4s %7s %10s %9s %12s %9s %8s %7s %9s %10s\n", "processes", "rank", "robots",
              "bytes/step", "msgs/step", "exchanging s", "waiting s", "other s", "CPU s", "MPI CPU s",
              "work CPU s");
  for (size_t i = 0; i < configs.size(); ++i) {
    if (configs[i].ranks == 0) continue;
    const Run& r = median_run(runs[i]);
    for (size_t k = 0; k < r.ranks.size(); ++k) {
      const RankRow& row = r.ranks[k];
      std::printf("%-22s %4zu %7d %10.0f %9.1f %12.3f %9.3f %8.3f %7.2f %9.2f %10.2f\n",
                  k == 0 ? label(configs[i]).c_str() : "", k, row.robots, row.bytes_per_step,
                  row.messages_per_step, row.exchanging_s, row.waiting_s, row.other_s, row.cpu_s,
                  row.mpi_cpu_s, row.work_cpu_s());
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> names;
  int repeats = 5;
  double sim_seconds = 10;
  std::string dir;
  auto app = troupe::cli::make_app(
      "mpi_scaling",
      {"mpi_scaling [strong] [weak] [huge] [--repeats N] [--sim-seconds S] [--dir DIR]",
       "troupe-sim divided between MPI processes, timed: strong scaling on 10,000 robots (alone, 1 and 2\n"
       "ranks), weak scaling at 5,000 robots a rank, and 100,000 robots at 1 and 2 ranks; the named\n"
       "tables, or all of them.\n",
       {"mpi_scaling strong --repeats 5", "mpi_scaling huge --repeats 3 --sim-seconds 5"}});
  app->add_option("TABLE", names, "tables to measure")->check(CLI::IsMember({"strong", "weak", "huge"}));
  app->add_option("--repeats", repeats, "runs of each configuration, alternated; medians (default 5)")
      ->type_name("N")
      ->check(troupe::cli::at_least(1));
  app->add_option("--sim-seconds", sim_seconds, "simulated seconds each run steps (default 10)")
      ->type_name("S")
      ->check(CLI::Range(0.1, 3600.0));
  app->add_option("--dir", dir, "where the worlds are written (default: a new temporary folder)")
      ->type_name("DIR");
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  if (names.empty()) names = {"strong", "weak", "huge"};
  // A folder of its own is removed at the end; one given (--dir) keeps its
  // worlds for the next run (the 100,000-robot one takes a while to write).
  const bool own_dir = dir.empty();
  if (own_dir) dir = troupe::testing::make_temp_dir("mpi-scaling-");
  struct Cleanup {
    bool own;
    const std::string& path;
    ~Cleanup() {
      if (own) troupe::testing::remove_tree(path);
    }
  } cleanup{own_dir, dir};
  if (geteuid() == 0) {
    // OpenMPI refuses root unless told twice.
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  }
  struct Table {
    const char* name;
    const char* title;
    std::vector<Config> configs;
    size_t base;
    bool weak;
  };
  const std::vector<Table> tables = {
      {"strong",
       "strong scaling: the scale row's 10,000-robot world",
       {{10000, 0}, {10000, 1}, {10000, 2}},
       0,
       false},
      {"weak", "weak scaling: 5,000 robots a rank", {{5000, 1}, {10000, 2}}, 0, true},
      {"huge", "100,000 robots (the scale row's density)", {{100000, 1}, {100000, 2}}, 0, false},
  };
  std::printf("mpi_scaling: %g simulated s a run, %d runs of each, alternated; %s\n", sim_seconds, repeats,
              MPIEXEC);
  for (const Table& t : tables) {
    if (std::find(names.begin(), names.end(), t.name) == names.end()) continue;
    for (const Config& c : t.configs) {
      if (std::filesystem::exists(world_path(dir, c.robots))) continue;
      std::string err;
      const std::string sub = std::filesystem::path(world_path(dir, c.robots)).parent_path().string();
      std::filesystem::create_directories(sub);
      if (troupe::bench::write_scale_world(sub, c.robots, err).empty()) {
        std::fprintf(stderr, "mpi_scaling: %s\n", err.c_str());
        return 1;
      }
    }
    std::fprintf(stderr, "%s\n", t.title);
    std::vector<std::vector<Run>> runs;
    if (!measure(dir, t.configs, repeats, sim_seconds, runs)) return 1;
    print_table(t.title, t.configs, runs, t.base, t.weak);
    std::fflush(stdout);
  }
  return 0;
}
