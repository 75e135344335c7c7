#include "drivers/common_desktop/log_map.h"

#include <algorithm>
#include <cstdlib>
#include <limits>

namespace troupe::desktop {
namespace {

// A beam usable as an endpoint: a return closer than both limits.
bool is_hit(const LaserReading& s, float r, double max_range) {
  return r > 0.01f && r < s.max_range - 1e-3 && r <= max_range;
}

// Cells of the segment (c0,r0)-(c1,r1) without the last one (Bresenham).
template <typename Visit>
void trace(int64_t c0, int64_t r0, int64_t c1, int64_t r1, Visit visit) {
  int64_t dc = std::llabs(c1 - c0), dr = -std::llabs(r1 - r0);
  int64_t sc = c0 < c1 ? 1 : -1, sr = r0 < r1 ? 1 : -1;
  int64_t err = dc + dr;
  while (c0 != c1 || r0 != r1) {
    visit(c0, r0);
    int64_t e2 = 2 * err;
    if (e2 >= dr) {
      err += dr;
      c0 += sc;
    }
    if (e2 <= dc) {
      err += dc;
      r0 += sr;
    }
  }
}

}  // namespace

bool build_log_map(std::span<const LaserReading> scans, const LogMapOptions& opt, OccupancyGrid& out,
                   std::string& error) {
  if (!(opt.resolution > 0) || !(opt.max_range > 0) || opt.margin < 0) {
    error = "resolution and max_range must be > 0 m, margin >= 0 m";
    return false;
  }
  double min_x = std::numeric_limits<double>::max(), min_y = min_x;
  double max_x = std::numeric_limits<double>::lowest(), max_y = max_x;
  size_t hits = 0;
  for (const LaserReading& s : scans) {
    min_x = std::min(min_x, s.laser_pose.x);
    max_x = std::max(max_x, s.laser_pose.x);
    min_y = std::min(min_y, s.laser_pose.y);
    max_y = std::max(max_y, s.laser_pose.y);
    for (size_t i = 0; i < s.ranges.size(); ++i) {
      if (!is_hit(s, s.ranges[i], opt.max_range)) continue;
      double b = s.laser_pose.a + s.start_angle + double(i) * s.angular_res;
      double x = s.laser_pose.x + s.ranges[i] * std::cos(b), y = s.laser_pose.y + s.ranges[i] * std::sin(b);
      min_x = std::min(min_x, x);
      max_x = std::max(max_x, x);
      min_y = std::min(min_y, y);
      max_y = std::max(max_y, y);
      ++hits;
    }
  }
  if (hits == 0) {
    error = "no laser returns to draw (" + std::to_string(scans.size()) + " scans)";
    return false;
  }
  Pose2 origin{min_x - opt.margin, min_y - opt.margin, 0};
  double w = std::ceil((max_x - min_x + 2 * opt.margin) / opt.resolution);
  double h = std::ceil((max_y - min_y + 2 * opt.margin) / opt.resolution);
  if (w * h > double(kMaxGridCells)) {
    error = "a " + std::to_string(int64_t(w)) + "x" + std::to_string(int64_t(h)) + " cell map is too large";
    return false;
  }
  OccupancyGrid grid(uint32_t(w), uint32_t(h), opt.resolution, origin);
  // Per cell: beams that ended in it, beams that crossed it.
  std::vector<uint32_t> ended(size_t(grid.width()) * grid.height(), 0), crossed(ended.size(), 0);
  auto index = [&](int64_t c, int64_t r) { return size_t(r) * grid.width() + size_t(c); };
  for (const LaserReading& s : scans) {
    int64_t c0 = 0, r0 = 0;
    grid.world_to_cell(s.laser_pose.x, s.laser_pose.y, c0, r0);
    for (size_t i = 0; i < s.ranges.size(); ++i) {
      float r = s.ranges[i];
      if (!(r > 0.01f)) continue;
      bool hit = is_hit(s, r, opt.max_range);
      double len = std::min<double>(r, opt.max_range);
      double b = s.laser_pose.a + s.start_angle + double(i) * s.angular_res;
      int64_t c1 = 0, r1 = 0;
      grid.world_to_cell(s.laser_pose.x + len * std::cos(b), s.laser_pose.y + len * std::sin(b), c1, r1);
      trace(c0, r0, c1, r1, [&](int64_t c, int64_t rr) {
        if (grid.contains(c, rr)) ++crossed[index(c, rr)];
      });
      if (hit && grid.contains(c1, r1)) ++ended[index(c1, r1)];
    }
  }
  for (uint32_t r = 0; r < grid.height(); ++r) {
    for (uint32_t c = 0; c < grid.width(); ++c) {
      size_t i = index(c, r);
      double seen = double(ended[i]) + crossed[i];
      if (ended[i] > 0 && ended[i] >= opt.occupied_ratio * seen) {
        grid.set(c, r, CellState::Occupied);
      } else if (crossed[i] > 0) {
        grid.set(c, r, CellState::Free);
      }
    }
  }
  out = std::move(grid);
  return true;
}

}  // namespace troupe::desktop
