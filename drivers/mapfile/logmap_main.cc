// troupe-logmap: draws an occupancy map from a CARMEN log's scans, seen from
// their (corrected) poses, and writes it as a PNG the mapfile driver reads.
//
//   troupe-logmap LOG -o MAP.png [--resolution M] [--max-range M] [--margin M]
#include <cstdio>
#include <string>

#include "drivers/common_desktop/carmen_log.h"
#include "drivers/common_desktop/log_map.h"
#include "wire/cli/args.h"

int main(int argc, char** argv) {
  std::string log_path, out_path;
  troupe::desktop::LogMapOptions opt;
  auto app = troupe::cli::make_app(
      "troupe logmap",
      {"troupe logmap LOG -o MAP.png [--resolution M] [--max-range M] [--margin M]",
       "Rasterises the laser endpoints of a CARMEN log (FLASER, ROBOTLASER1; plain\n"
       "or gzip) seen from each scan's pose into an occupancy map: endpoints are\n"
       "occupied, cells the beams crossed are free, the rest unknown. Use a\n"
       "SLAM-corrected log: raw odometry poses smear the walls. Prints the\n"
       "origin and resolution, as the mapfile driver's options.\n",
       {"troupe-logmap aces-corrected.log.gz -o aces.png --resolution 0.05",
        "troupe logmap run.log -o run.png --max-range 8 --margin 0.5"}});
  app->add_option("LOG", log_path, "the CARMEN log")->required();
  app->add_option("-o", out_path, "the map to write (PNG)")->type_name("MAP.png")->required();
  app->add_option("--resolution", opt.resolution, "cell size, m (default 0.05)")
      ->type_name("M")
      ->check(troupe::cli::above(0) & troupe::cli::at_most(1e6));
  app->add_option("--max-range", opt.max_range, "longer beams are not drawn, m (default 30)")
      ->type_name("M")
      ->check(troupe::cli::above(0) & troupe::cli::at_most(1e6));
  app->add_option("--margin", opt.margin, "border around the outermost endpoint, m (default 1)")
      ->type_name("M")
      ->check(troupe::cli::between(0, 1e6));
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  troupe::desktop::CarmenLog log;
  std::string error;
  if (!troupe::desktop::read_carmen(log_path.c_str(), log, error)) {
    std::fprintf(stderr, "troupe-logmap: %s\n", error.c_str());
    return 1;
  }
  for (const std::string& e : log.errors) std::fprintf(stderr, "troupe-logmap: %s (skipped)\n", e.c_str());
  troupe::desktop::OccupancyGrid grid;
  if (!troupe::desktop::build_log_map(log.scans, opt, grid, error) ||
      !troupe::desktop::save_png_map(out_path.c_str(), grid, error)) {
    std::fprintf(stderr, "troupe-logmap: %s: %s\n", log_path.c_str(), error.c_str());
    return 1;
  }
  std::printf("%s: %zu scans, %zu malformed lines skipped\n", log_path.c_str(), log.scans.size(), log.error_count);
  std::printf("%s: %ux%u cells, resolution %.3f m, origin (%.3f, %.3f) m\n", out_path.c_str(), grid.width(),
              grid.height(), grid.resolution(), grid.origin().x, grid.origin().y);
  std::printf(
      "mapfile options: { \"file\": \"%s\", \"resolution\": %g, \"origin_x\": %.3f, \"origin_y\": %.3f }\n",
      out_path.c_str(), grid.resolution(), grid.origin().x, grid.origin().y);
  return 0;
}
