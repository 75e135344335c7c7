// troupe-logmap: draws an occupancy map from a CARMEN log's scans, seen from
// their (corrected) poses, and writes it as a PNG the mapfile driver reads.
//
//   troupe-logmap LOG -o MAP.png [--resolution M] [--max-range M] [--margin M]
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "drivers/common_desktop/carmen_log.h"
#include "drivers/common_desktop/log_map.h"

namespace {

const char kUsage[] =
    "usage: troupe-logmap LOG -o MAP.png [--resolution M] [--max-range M] [--margin M]\n"
    "\n"
    "Rasterises the laser endpoints of a CARMEN log (FLASER, ROBOTLASER1; plain\n"
    "or gzip) seen from each scan's pose into an occupancy map: endpoints are\n"
    "occupied, cells the beams crossed are free, the rest unknown. Use a\n"
    "SLAM-corrected log: raw odometry poses smear the walls. Prints the\n"
    "origin and resolution, as the mapfile driver's options.\n"
    "\n"
    "  --resolution M  cell size, m (default 0.05)\n"
    "  --max-range M   longer beams are not drawn, m (default 30)\n"
    "  --margin M      border around the outermost endpoint, m (default 1)\n"
    "\n"
    "examples:\n"
    "  troupe-logmap aces-corrected.log.gz -o aces.png --resolution 0.05\n"
    "  troupe logmap run.log -o run.png --max-range 8 --margin 0.5\n";

bool parse_positive(const char* text, double& out) {
  char* end = nullptr;
  out = std::strtod(text, &end);
  return end != text && *end == '\0' && out > 0 && out < 1e6;
}

}  // namespace

int main(int argc, char** argv) {
  const char* log_path = nullptr;
  const char* out_path = nullptr;
  troupe::desktop::LogMapOptions opt;
  for (int i = 1; i < argc; ++i) {
    auto value = [&](const char* flag) -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "troupe-logmap: %s needs a value\n%s", flag, kUsage);
        std::exit(2);
      }
      return argv[++i];
    };
    auto number = [&](const char* flag, double& out, bool allow_zero) {
      const char* v = value(flag);
      if (!(parse_positive(v, out) || (allow_zero && std::strcmp(v, "0") == 0 && (out = 0, true)))) {
        std::fprintf(stderr, "troupe-logmap: %s '%s' is not a positive number\n", flag, v);
        std::exit(2);
      }
    };
    if (std::strcmp(argv[i], "-h") == 0 || std::strcmp(argv[i], "--help") == 0) {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (std::strcmp(argv[i], "-o") == 0) {
      out_path = value("-o");
    } else if (std::strcmp(argv[i], "--resolution") == 0) {
      number("--resolution", opt.resolution, false);
    } else if (std::strcmp(argv[i], "--max-range") == 0) {
      number("--max-range", opt.max_range, false);
    } else if (std::strcmp(argv[i], "--margin") == 0) {
      number("--margin", opt.margin, true);
    } else if (argv[i][0] == '-' || log_path != nullptr) {
      std::fprintf(stderr, "troupe-logmap: unexpected argument '%s'\n%s", argv[i], kUsage);
      return 2;
    } else {
      log_path = argv[i];
    }
  }
  if (log_path == nullptr || out_path == nullptr) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  troupe::desktop::CarmenLog log;
  std::string error;
  if (!troupe::desktop::read_carmen(log_path, log, error)) {
    std::fprintf(stderr, "troupe-logmap: %s\n", error.c_str());
    return 1;
  }
  for (const std::string& e : log.errors) std::fprintf(stderr, "troupe-logmap: %s (skipped)\n", e.c_str());
  troupe::desktop::OccupancyGrid grid;
  if (!troupe::desktop::build_log_map(log.scans, opt, grid, error) ||
      !troupe::desktop::save_png_map(out_path, grid, error)) {
    std::fprintf(stderr, "troupe-logmap: %s: %s\n", log_path, error.c_str());
    return 1;
  }
  std::printf("%s: %zu scans, %zu malformed lines skipped\n", log_path, log.scans.size(), log.error_count);
  std::printf("%s: %ux%u cells, resolution %.3f m, origin (%.3f, %.3f) m\n", out_path, grid.width(),
              grid.height(), grid.resolution(), grid.origin().x, grid.origin().y);
  std::printf(
      "mapfile options: { \"file\": \"%s\", \"resolution\": %g, \"origin_x\": %.3f, \"origin_y\": %.3f }\n",
      out_path, grid.resolution(), grid.origin().x, grid.origin().y);
  return 0;
}
