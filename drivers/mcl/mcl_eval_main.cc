// troupe-mcl-eval: localization accuracy on a recorded CARMEN log in one
// command. Builds the map from the log's corrected poses, replays the log
// with odometry made from those poses plus seeded drift and slip, runs MCL
// against the real scans and compares every estimate with the corrected
// pose. The last line is the summary:
//   mean_m=... max_m=... mean_deg=... within_10cm=... said_lost=...
//   unaware_off=... noticed_s=... recovered_s=...
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "drivers/common_desktop/mcl_eval.h"

namespace {

const char kUsage[] =
    "usage: troupe-mcl-eval LOG [--seed N] [--particles N] [--beams N] [--resolution M] [--global]\n"
    "                       [--sigma-hit M] [--motion-noise A] [--candidates N] [--kidnap SCAN]\n"
    "                       [--jump X,Y,DEG] [--per-scan]\n"
    "\n"
    "Monte Carlo localization on a CARMEN log (FLASER or ROBOTLASER1 lines; plain\n"
    "or gzip) whose scan poses are SLAM-corrected. The map is drawn from those\n"
    "poses; odometry is made from them with seeded drift and slip; MCL runs\n"
    "against the real scans; each estimate is compared with the corrected pose.\n"
    "\n"
    "  --seed N        seeds the odometry noise and the filter (default 1)\n"
    "  --particles N   most particles (KLD sampling adapts below; default 5000)\n"
    "  --beams N       beams used per scan (default 60)\n"
    "  --resolution M  map cell size, m (default 0.05)\n"
    "  --global        start from uniform particles, not the first pose\n"
    "  --sigma-hit M   likelihood field's range error sigma, m (default 0.2)\n"
    "  --motion-noise A  all four odometry noise alphas (default 0.01)\n"
    "  --candidates N  poses scored against the scan per update while lost, the\n"
    "                  best injected (default 20000; 0: uniform poses injected)\n"
    "  --kidnap SCAN   the kidnapped robot: from scan SCAN on, the replayed\n"
    "                  odometry jumps by --jump (the filter takes it as motion)\n"
    "  --jump X,Y,DEG  the jump in the robot's frame: m, m, degrees (default 0,4,90)\n"
    "  --per-scan      print every scan's error\n"
    "\n"
    "The summary's said_lost is the share of scans after which the filter said\n"
    "it was lost, unaware_off the share where the estimate was over 1 m off\n"
    "while the filter did not say so. noticed_s and recovered_s count from the\n"
    "kidnapping (or the first scan): until the filter first said it was lost,\n"
    "and until the estimate stays within 1 m to the end (-1: never).\n"
    "\n"
    "examples:\n"
    "  troupe-mcl-eval aces-corrected.log.gz --seed 3 --particles 2000\n"
    "  troupe mcl-eval aces-corrected.log.gz --global --per-scan   # from no idea where it is\n"
    "  troupe mcl-eval aces-corrected.log.gz --kidnap 220           # carried off mid-log\n";

bool parse_count(const char* text, uint64_t max, uint64_t& out) {
  char* end = nullptr;
  unsigned long long v = std::strtoull(text, &end, 10);
  if (end == text || *end != '\0' || text[0] == '-' || v > max) return false;
  out = v;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace troupe::desktop;
  const char* log_path = nullptr;
  EvalOptions opt;
  bool per_scan = false;
  for (int i = 1; i < argc; ++i) {
    auto value = [&](const char* flag) -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "troupe-mcl-eval: %s needs a value\n%s", flag, kUsage);
        std::exit(2);
      }
      return argv[++i];
    };
    auto count = [&](const char* flag, uint64_t min, uint64_t max) -> uint64_t {
      const char* v = value(flag);
      uint64_t n = 0;
      if (!parse_count(v, max, n) || n < min) {
        std::fprintf(stderr, "troupe-mcl-eval: %s '%s' must be a whole number in [%llu, %llu]\n", flag, v,
                     (unsigned long long)min, (unsigned long long)max);
        std::exit(2);
      }
      return n;
    };
    if (std::strcmp(argv[i], "-h") == 0 || std::strcmp(argv[i], "--help") == 0) {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (std::strcmp(argv[i], "--seed") == 0) {
      opt.seed = count("--seed", 0, UINT64_MAX);
    } else if (std::strcmp(argv[i], "--particles") == 0) {
      opt.mcl.max_particles = count("--particles", 1, 1'000'000);
      opt.mcl.min_particles = std::min(opt.mcl.min_particles, opt.mcl.max_particles);
    } else if (std::strcmp(argv[i], "--beams") == 0) {
      opt.mcl.max_beams = count("--beams", 1, 100'000);
    } else if (std::strcmp(argv[i], "--resolution") == 0) {
      const char* v = value("--resolution");
      char* end = nullptr;
      opt.map.resolution = std::strtod(v, &end);
      if (end == v || *end != '\0' || !(opt.map.resolution >= 0.01 && opt.map.resolution <= 1)) {
        std::fprintf(stderr, "troupe-mcl-eval: --resolution '%s' must be in [0.01, 1] m\n", v);
        return 2;
      }
    } else if (std::strcmp(argv[i], "--sigma-hit") == 0 || std::strcmp(argv[i], "--motion-noise") == 0) {
      const char* flag = argv[i];
      const char* v = value(flag);
      char* end = nullptr;
      double x = std::strtod(v, &end);
      if (end == v || *end != '\0' || !(x > 0 && x <= 10)) {
        std::fprintf(stderr, "troupe-mcl-eval: %s '%s' must be in (0, 10]\n", flag, v);
        return 2;
      }
      if (flag[2] == 's') {
        opt.mcl.sensor.sigma_hit = x;
      } else {
        opt.mcl.motion = {x, x, x, x};
      }
    } else if (std::strcmp(argv[i], "--candidates") == 0) {
      opt.mcl.recovery_candidates = count("--candidates", 0, 10'000'000);
    } else if (std::strcmp(argv[i], "--kidnap") == 0) {
      opt.kidnap_scan = count("--kidnap", 0, 100'000'000);
    } else if (std::strcmp(argv[i], "--jump") == 0) {
      const char* v = value("--jump");
      double x = 0, y = 0, deg = 0;
      char tail = 0;
      if (std::sscanf(v, "%lf,%lf,%lf%c", &x, &y, &deg, &tail) != 3 || !std::isfinite(x) ||
          !std::isfinite(y) || !std::isfinite(deg) || std::fabs(x) > 1e4 || std::fabs(y) > 1e4) {
        std::fprintf(stderr,
                     "troupe-mcl-eval: --jump '%s' must be X,Y,DEG (m, m, degrees; |X|, |Y| <= 10000)\n", v);
        return 2;
      }
      opt.kidnap_jump = {x, y, wrap_angle(deg * kPi / 180)};
    } else if (std::strcmp(argv[i], "--global") == 0) {
      opt.global = true;
    } else if (std::strcmp(argv[i], "--per-scan") == 0) {
      per_scan = true;
    } else if (argv[i][0] == '-' || log_path != nullptr) {
      std::fprintf(stderr, "troupe-mcl-eval: unexpected argument '%s'\n%s", argv[i], kUsage);
      return 2;
    } else {
      log_path = argv[i];
    }
  }
  if (log_path == nullptr) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  CarmenLog log;
  std::string error;
  if (!read_carmen(log_path, log, error)) {
    std::fprintf(stderr, "troupe-mcl-eval: %s\n", error.c_str());
    return 1;
  }
  for (const std::string& e : log.errors) std::fprintf(stderr, "troupe-mcl-eval: %s (skipped)\n", e.c_str());
  if (opt.kidnap_scan != EvalOptions::kNoKidnap && opt.kidnap_scan >= log.scans.size()) {
    std::fprintf(stderr, "troupe-mcl-eval: --kidnap %zu: the log has %zu scans (0 to %zu)\n", opt.kidnap_scan,
                 log.scans.size(), log.scans.size() - 1);
    return 2;
  }
  EvalResult result;
  if (!evaluate_log(log, opt, result, error)) {
    std::fprintf(stderr, "troupe-mcl-eval: %s: %s\n", log_path, error.c_str());
    return 1;
  }
  const OccupancyGrid& map = result.map;
  std::printf("log: %s: %zu scans of %zu beams, %zu malformed lines skipped\n", log_path, log.scans.size(),
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
