// troupe-mcl-eval: localization accuracy on a recorded CARMEN log in one
// command. Builds the map from the log's corrected poses, replays the log
// with odometry made from those poses plus seeded drift and slip, runs MCL
// against the real scans and compares every estimate with the corrected
// pose. The last line is the summary:
//   mean_m=... max_m=... mean_deg=... within_10cm=... said_lost=...
//   unaware_off=... noticed_s=... recovered_s=...
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "drivers/common_desktop/mcl_eval.h"
#include "wire/cli/args.h"

int main(int argc, char** argv) {
  using namespace troupe::desktop;
  std::string log_path;
  EvalOptions opt;
  bool per_scan = false;
  double motion_noise = 0;
  std::vector<double> jump;
  auto app = troupe::cli::make_app(
      "troupe mcl-eval",
      {"troupe mcl-eval LOG [--seed N] [--particles N] [--beams N] [--resolution M] [--global]\n"
       "                       [--sigma-hit M] [--motion-noise A] [--candidates N] [--kidnap SCAN]\n"
       "                       [--jump X,Y,DEG] [--per-scan]",
       "Monte Carlo localization on a CARMEN log (FLASER or ROBOTLASER1 lines; plain\n"
       "or gzip) whose scan poses are SLAM-corrected. The map is drawn from those\n"
       "poses; odometry is made from them with seeded drift and slip; MCL runs\n"
       "against the real scans; each estimate is compared with the corrected pose.\n"
       "\n"
       "The summary's said_lost is the share of scans after which the filter said\n"
       "it was lost, unaware_off the share where the estimate was over 1 m off\n"
       "while the filter did not say so. noticed_s and recovered_s count from the\n"
       "kidnapping (or the first scan): until the filter first said it was lost,\n"
       "and until the estimate stays within 1 m to the end (-1: never).\n",
       {"troupe-mcl-eval aces-corrected.log.gz --seed 3 --particles 2000",
        "troupe mcl-eval aces-corrected.log.gz --global --per-scan   # from no idea where it is",
        "troupe mcl-eval aces-corrected.log.gz --kidnap 220           # carried off mid-log"}});
  app->add_option("LOG", log_path, "the CARMEN log")->required();
  app->add_option("--seed", opt.seed, "seeds the odometry noise and the filter (default 1)")->type_name("N");
  app->add_option("--particles", opt.mcl.max_particles, "most particles (KLD sampling adapts below; default 5000)")
      ->type_name("N")
      ->check(troupe::cli::at_least(1) & troupe::cli::at_most(1'000'000));
  app->add_option("--beams", opt.mcl.max_beams, "beams used per scan (default 60)")
      ->type_name("N")
      ->check(troupe::cli::at_least(1) & troupe::cli::at_most(100'000));
  app->add_option("--resolution", opt.map.resolution, "map cell size, m (default 0.05)")
      ->type_name("M")
      ->check(troupe::cli::at_least(0.01) & troupe::cli::at_most(1));
  app->add_flag("--global", opt.global, "start from uniform particles, not the first pose");
  app->add_option("--sigma-hit", opt.mcl.sensor.sigma_hit, "likelihood field's range error sigma, m (default 0.2)")
      ->type_name("M")
      ->check(troupe::cli::above(0) & troupe::cli::at_most(10));
  CLI::Option* noise = app->add_option("--motion-noise", motion_noise, "all four odometry noise alphas (default 0.01)")
      ->type_name("A")
      ->check(troupe::cli::above(0) & troupe::cli::at_most(10));
  app->add_option("--candidates", opt.mcl.recovery_candidates,
                  "poses scored against the scan per update while lost, the best injected\n"
                  "(default 20000; 0: uniform poses injected)")
      ->type_name("N")
      ->check(troupe::cli::at_most(10'000'000));
  app->add_option("--kidnap", opt.kidnap_scan,
                  "the kidnapped robot: from scan SCAN on, the replayed odometry jumps by\n"
                                        "--jump (the filter takes it as motion)")
                            ->type_name("SCAN");
  app->add_option("--jump", jump, "the jump in the robot's frame: m, m, degrees (default 0,4,90; |X|, |Y| <= 10000)")
      ->type_name("X,Y,DEG")
      ->delimiter(',')
      ->expected(3)
      ->check(troupe::cli::at_least(-1e4) & troupe::cli::at_most(1e4));
  app->add_flag("--per-scan", per_scan, "print every scan's error");
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  opt.mcl.min_particles = std::min(opt.mcl.min_particles, opt.mcl.max_particles);
  if (noise->count() > 0) opt.mcl.motion = {motion_noise, motion_noise, motion_noise, motion_noise};
  if (jump.size() == 3) opt.kidnap_jump = {jump[0], jump[1], wrap_angle(jump[2] * kPi / 180)};
  CarmenLog log;
  std::string error;
  if (!read_carmen(log_path.c_str(), log, error)) {
    std::fprintf(stderr, "troupe-mcl-eval: %s\n", error.c_str());
    return 1;
  }
  for (const std::string& e : log.errors) std::fprintf(stderr, "troupe-mcl-eval: %s (skipped)\n", e.c_str());
  if (opt.kidnap_scan != EvalOptions::kNoKidnap && opt.kidnap_scan >= log.scans.size()) {
    return troupe::cli::usage_error(*app, "--kidnap " + std::to_string(opt.kidnap_scan) + ": the log has " +
                                              std::to_string(log.scans.size()) + " scans (0 to " +
                                              std::to_string(log.scans.size() - 1) + ")");
  }
  EvalResult result;
  if (!evaluate_log(log, opt, result, error)) {
    std::fprintf(stderr, "troupe-mcl-eval: %s: %s\n", log_path.c_str(), error.c_str());
    return 1;
  }
  const OccupancyGrid& map = result.map;
  std::printf("log: %s: %zu scans of %zu beams, %zu malformed lines skipped\n", log_path.c_str(), log.scans.size(),
              log.scans.front().ranges.size(), log.error_count);
  std::printf("map: %ux%u cells, resolution %.3f m, origin (%.3f, %.3f) m\n", map.width(), map.height(),
              map.resolution(), map.origin().x, map.origin().y);
  std::printf("mcl: %s, particles %zu..%zu, %zu beams, seed %llu, recovery %s\n",
              opt.global ? "global start" : "tracking", opt.mcl.min_particles, opt.mcl.max_particles,
              opt.mcl.max_beams, (unsigned long long)opt.seed,
              opt.mcl.recovery_candidates == 0
                  ? "uniform"
                  : ("best of " + std::to_string(opt.mcl.recovery_candidates)).c_str());
  if (opt.kidnap_scan != EvalOptions::kNoKidnap) {
    std::printf("kidnap: at scan %zu (%.2f s) the odometry jumps by (%.2f m, %.2f m, %.1f deg)\n",
                opt.kidnap_scan, result.kidnap_time_s, opt.kidnap_jump.x, opt.kidnap_jump.y,
                opt.kidnap_jump.a * 180 / kPi);
  }
  if (per_scan) {
    std::printf("%6s %10s %9s %9s %9s %5s\n", "scan", "time_s", "err_m", "err_deg", "particles", "lost");
    for (size_t i = 0; i < result.scans.size(); ++i) {
      const ScanError& e = result.scans[i];
      std::printf("%6zu %10.2f %9.3f %9.2f %9zu %5s\n", i, e.time_s, e.trans_m, e.angle_rad * 180 / kPi,
                  e.particles, e.lost ? "lost" : "-");
    }
  }
  const EvalSummary& s = result.summary;
  std::printf("scans %zu, max_deg %.2f, mean particles %.0f, filter time %.1f ms per scan\n",
              result.scans.size(), s.max_deg, s.mean_particles,
              1e3 * result.filter_seconds / double(result.scans.size()));
  std::printf(
      "mean_m=%.3f max_m=%.3f mean_deg=%.2f within_10cm=%.3f said_lost=%.3f unaware_off=%.3f "
      "noticed_s=%.1f recovered_s=%.1f\n",
      s.mean_m, s.max_m, s.mean_deg, s.within_10cm, s.said_lost, s.unaware_off, s.noticed_s, s.recovered_s);
  return 0;
}
