// MCL accuracy, three tables.
//
//   bench_mcl_accuracy [--seeds N]
//
// 1. The ACES log (TROUPE_SHARED_DATA/carmen): what troupe-mcl-eval does,
//    over N seeds and several particle limits.
//    Then lost detection and recovery on the same log, for both recovery
//    methods: the odometry jumped mid-log (troupe-mcl-eval --kidnap) and a
//    global start; how soon the filter says it is lost, how soon it is back
//    on track, and how much of the log it spent lost or unaware.
// 2. The cave world (Stage's cave.png, 16 x 16 m) with this program's own
//    ray caster standing in for troupe-sim: a robot wanders for 120 s at
//    10 Hz with a 180-beam, 8 m laser and drifting, slipping odometry.
//    Pose tracking error, and how long global localization takes to lock
//    on (error below 0.25 m from then on).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "drivers/common_desktop/mcl_eval.h"
#include "tests/desktop/synthetic_world.h"
#include "wire/cli/args.h"

using namespace troupe::desktop;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

// The kidnapped robot and the global start on the ACES log, both recovery
// methods: the best-scoring of 20,000 scored candidates (the default) and
// uniform free-space poses (classic augmented MCL).
void recovery_table(const CarmenLog& log, int seeds) {
  struct Case {
    const char* name;
    size_t kidnap_scan;
    Pose2 jump;
    bool global;
  };
  const Case cases[] = {
      {"odometry jumps (0 m, 4 m, 90 deg) at scan 220", 220, {0, 4, kPi / 2}, false},
      {"odometry jumps (2 m, -3 m, 180 deg) at scan 100", 100, {2, -3, kPi}, false},
      {"global start", EvalOptions::kNoKidnap, {}, true},
  };
  std::printf("ACES log, lost and found, %d seeds: median [worst] over seeds (-1: never)\n\n", seeds);
  std::printf(
      "| case | recovery | said lost after s | on track after s | said_lost | unaware_off | mean_m |\n");
  std::printf("|---|---|---:|---:|---:|---:|---:|\n");
  for (const Case& c : cases) {
    for (size_t candidates : {size_t(20000), size_t(0)}) {
      std::vector<double> noticed, recovered, lost, unaware, mean_m;
      for (int s = 1; s <= seeds; ++s) {
        EvalOptions opt;
        opt.seed = uint64_t(s);
        opt.global = c.global;
        opt.kidnap_scan = c.kidnap_scan;
        opt.kidnap_jump = c.jump;
        opt.mcl.recovery_candidates = candidates;
        EvalResult r;
        std::string error;
        if (!evaluate_log(log, opt, r, error)) {
          std::printf("error: %s\n", error.c_str());
          return;
        }
        // "never" sorts last.
        noticed.push_back(r.summary.noticed_s < 0 ? INFINITY : r.summary.noticed_s);
        recovered.push_back(r.summary.recovered_s < 0 ? INFINITY : r.summary.recovered_s);
        lost.push_back(r.summary.said_lost);
        unaware.push_back(r.summary.unaware_off);
        mean_m.push_back(r.summary.mean_m);
      }
      auto worst = [](const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); };
      auto secs = [](double v) { return std::isinf(v) ? -1.0 : v; };
      std::printf("| %s | %s | %.1f [%.1f] | %.1f [%.1f] | %.3f [%.3f] | %.3f [%.3f] | %.3f [%.3f] |\n",
                  c.name, candidates ? "best of 20000 scored" : "uniform", secs(median(noticed)),
                  secs(worst(noticed)), secs(median(recovered)), secs(worst(recovered)), median(lost),
                  worst(lost), median(unaware), worst(unaware), median(mean_m), worst(mean_m));
      std::fflush(stdout);
    }
  }
  std::printf("\n");
}

void aces_table(int seeds) {
  std::string path = std::string(TROUPE_SHARED_DATA) + "/carmen/aces-corrected.log.gz";
  CarmenLog log;
  std::string error;
  if (!std::ifstream(path) || !read_carmen(path, log, error)) {
    std::printf("ACES log: skipped (%s not found)\n\n", path.c_str());
    return;
  }
  std::printf("ACES log (440 scans, corrected poses as truth), %d seeds: median [worst] over seeds\n\n",
              seeds);
  std::printf("| particles (max) | mean_m | max_m | mean_deg | within_10cm | ms per scan |\n");
  std::printf("|---:|---:|---:|---:|---:|---:|\n");
  for (size_t n : {500, 2000, 5000}) {
    std::vector<double> mean_m, max_m, mean_deg, within, ms;
    for (int s = 1; s <= seeds; ++s) {
      EvalOptions opt;
      opt.seed = uint64_t(s);
      opt.mcl.max_particles = n;
      opt.mcl.min_particles = std::min<size_t>(opt.mcl.min_particles, n);
      EvalResult r;
      if (!evaluate_log(log, opt, r, error)) {
        std::printf("error: %s\n", error.c_str());
        return;
      }
      mean_m.push_back(r.summary.mean_m);
      max_m.push_back(r.summary.max_m);
      mean_deg.push_back(r.summary.mean_deg);
      within.push_back(r.summary.within_10cm);
      ms.push_back(1e3 * r.filter_seconds / double(r.scans.size()));
    }
    std::printf("| %zu | %.3f [%.3f] | %.3f [%.3f] | %.2f [%.2f] | %.3f [%.3f] | %.2f |\n", n, median(mean_m),
                *std::max_element(mean_m.begin(), mean_m.end()), median(max_m),
                *std::max_element(max_m.begin(), max_m.end()), median(mean_deg),
                *std::max_element(mean_deg.begin(), mean_deg.end()), median(within),
                *std::min_element(within.begin(), within.end()), median(ms));
  }
  std::printf("\n");
  recovery_table(log, seeds);
}

// A wandering robot: forward at 0.4 m/s, turning away from the nearer side,
// turning on the spot when something is close ahead. Poses every dt.
std::vector<Pose2> wander(const OccupancyGrid& map, Pose2 start, double seconds, double dt, Rng& rng) {
  testing::TestLaser probe;
  probe.beams = 37;
  probe.max_range = 3.0;
  std::vector<Pose2> out{start};
  Pose2 p = start;
  double turn_bias = 0;
  for (double t = 0; t < seconds; t += dt) {
    std::vector<float> r = testing::cast_scan(map, p, probe);
    float right = *std::min_element(r.begin(), r.begin() + 15);
    float front = *std::min_element(r.begin() + 12, r.begin() + 25);
    float left = *std::min_element(r.begin() + 22, r.end());
    if (uniform01(rng) < 0.02) turn_bias = (uniform01(rng) - 0.5) * 0.6;
    double v = front < 0.7 ? 0.0 : 0.4, w = turn_bias;
    if (front < 1.2 || std::min(left, right) < 0.5) w = left > right ? 0.8 : -0.8;
    p = {p.x + v * std::cos(p.a) * dt, p.y + v * std::sin(p.a) * dt, wrap_angle(p.a + w * dt)};
    out.push_back(p);
  }
  return out;
}

struct CaveRun {
  double mean_m = 0, max_m = 0, mean_deg = 0, lock_s = -1;
};

CaveRun run_cave(const OccupancyGrid& map, uint64_t seed, bool global) {
  Rng world(seed), rng(seed + 7);
  const double dt = 0.1;
  std::vector<Pose2> route = wander(map, {-6.946, -6.947, kPi / 4}, 120.0, dt, world);
  MclParams p;  // the driver's defaults, with the laser's range
  p.sensor.max_range = p.laser_max_range = 8.0;
  ParticleFilter filter(map, p);
  if (global) {
    filter.init_global(rng);
  } else {
    filter.init_pose(route[0], Eigen::Vector3d(0.01, 0.01, 0.0025).asDiagonal(), rng);
  }
  OdometryNoise noise;  // drift 2% and 0.02 rad/m, slip 2% of steps
  OdometrySynthesizer odometry(noise, world);
  testing::TestLaser laser;
  laser.beams = 180;
  std::vector<double> err;
  CaveRun r;
  for (size_t i = 0; i < route.size(); ++i) {
    Pose2 odom = odometry.next(route[i], world);
    std::vector<float> ranges = testing::cast_scan(map, route[i], laser);
    for (float& x : ranges) {
      if (x < laser.max_range) x = std::max(0.0f, x + float(gaussian(world, 0.01)));
    }
    filter.update(odom, {laser.start_angle(), laser.angular_res(), laser.max_range, ranges}, rng);
    Pose2 best = filter.best();
    double e = distance(best, route[i]);
    err.push_back(e);
    r.mean_m += e;
    r.max_m = std::max(r.max_m, e);
    r.mean_deg += std::fabs(wrap_angle(best.a - route[i].a)) * 180 / kPi;
  }
  r.mean_m /= double(err.size());
  r.mean_deg /= double(err.size());
  size_t lock = err.size();
  for (size_t i = err.size(); i-- > 0 && err[i] < 0.25;) lock = i;
  r.lock_s = lock < err.size() ? double(lock) * dt : -1;
  return r;
}

void cave_table(int seeds) {
  std::string path = std::string(TROUPE_SHARED_DATA) + "/stage/bitmaps/cave.png";
  PngMapOptions png;
  png.resolution = 16.0 / 500.0;  // simple.world scales the 500 px bitmap to 16 m
  png.origin = {-8.0, -8.0, 0.0};
  OccupancyGrid map;
  std::string error;
  if (!std::ifstream(path) || !load_png_map(path, png, map, error)) {
    std::printf("cave world: skipped (%s not found)\n", path.c_str());
    return;
  }
  // map.inc's floorplan has "boundary 1": Stage walls the bitmap in.
  for (uint32_t c = 0; c < map.width(); ++c) {
    map.set(c, 0, CellState::Occupied);
    map.set(c, map.height() - 1, CellState::Occupied);
  }
  for (uint32_t r = 0; r < map.height(); ++r) {
    map.set(0, r, CellState::Occupied);
    map.set(map.width() - 1, r, CellState::Occupied);
  }
  std::printf("Cave world (own ray caster, 120 s wander at 10 Hz, driver defaults), %d seeds\n\n", seeds);
  std::printf("| seed | tracking mean_m | tracking max_m | tracking mean_deg | global: locked after s |\n");
  std::printf("|---:|---:|---:|---:|---:|\n");
  std::vector<double> means, degs, locks;
  for (int s = 1; s <= seeds; ++s) {
    CaveRun t = run_cave(map, uint64_t(s), false), g = run_cave(map, uint64_t(s), true);
    std::printf("| %d | %.3f | %.3f | %.2f | %s |\n", s, t.mean_m, t.max_m, t.mean_deg,
                g.lock_s < 0 ? "never" : std::to_string(g.lock_s).substr(0, 4).c_str());
    means.push_back(t.mean_m);
    degs.push_back(t.mean_deg);
    locks.push_back(g.lock_s < 0 ? 1e9 : g.lock_s);
  }
  std::printf("| median | %.3f | | %.2f | %.1f |\n\n", median(means), median(degs), median(locks));
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 5;
  auto app =
      troupe::cli::make_app("bench_mcl_accuracy", {"bench_mcl_accuracy [--seeds N]",
                                                   "MCL accuracy tables: the ACES log, and the cave world.\n",
                                                   {"bench_mcl_accuracy --seeds 3"}});
  app->add_option("--seeds", seeds, "runs per table, seeds 1..N (default 5)")
      ->type_name("N")
      ->check(troupe::cli::at_least(1));
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  aces_table(seeds);
  cave_table(seeds);
  return 0;
}
