// Occupancy maps drawn from laser scans taken at known poses (for example a
// SLAM-corrected CARMEN log): troupe-logmap and troupe-mcl-eval build their
// maps with it.
#pragma once

#include <span>

#include "drivers/common_desktop/carmen_log.h"
#include "drivers/common_desktop/occupancy_grid.h"

namespace troupe::desktop {

struct LogMapOptions {
  /// Cell side, m.
  double resolution = 0.05;
  /// Free border around the outermost endpoint, m.
  double margin = 1.0;
  /// Beams longer than this are not drawn (distant returns are sparse and
  /// blur the walls), m.
  double max_range = 30.0;
  /// A cell is occupied when at least this share of the beams that reached
  /// it ended in it (people walking by leave a few hits among many passes).
  double occupied_ratio = 0.25;
};

/// Rasterises every scan's endpoints (occupied) and the cells its beams
/// crossed (free), seen from each scan's laser_pose. Cells no beam reached
/// are unknown. False with `error` when there is nothing to draw or the grid
/// would be too large.
bool build_log_map(std::span<const LaserReading> scans, const LogMapOptions& options, OccupancyGrid& out,
                   std::string& error);

}  // namespace troupe::desktop
