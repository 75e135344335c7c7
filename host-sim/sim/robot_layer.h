// The robots as a per-step occupancy layer for rangers, as Stage draws its
// models into the grid it ray-traces: a coarse grid whose every cell lists
// the robots whose circles overlap it. A beam walks the cells it crosses,
// nearest first, and tests only the robots listed there, stopping at the
// first cell that starts beyond the nearest hit so far. In a packed crowd a
// beam so tests the few robots in front of it instead of every robot within
// its reach (a few hundred).
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "host-sim/sim/geometry.h"
#include "host-sim/sim/spatial_hash.h"

namespace troupe::sim {

class RobotLayer {
 public:
  /// A robot as the layer lists it.
  struct Entry {
    uint32_t index;  // the robot
    uint32_t order;  // its place in the spatial hash's order (ties go to the lower)
    float x, y;      // circle centre, world, m
    float r;         // circle radius, m (the hash's, padded for its float rounding)
  };

  /// Rebuilds from the hash's robots whose flags have a bit of `flags`.
  void build(const SpatialHash& hash, uint32_t flags);

  /// Calls visit(entries, entry_t) for each cell the ray from `o` along
  /// `dir` (unit) crosses before `t_max` (m), nearest first, where entry_t
  /// is the distance (m) at which the ray enters the cell. visit returns the
  /// distance beyond which nothing more is wanted; the walk ends at the first
  /// cell entered beyond it. A robot overlapping several cells is visited
  /// in each.
  template <class Visit>
  void walk(Vec2 o, Vec2 dir, double t_max, Visit&& visit) const;

  size_t memory_bytes() const { return start_.capacity() * 4 + entries_.capacity() * sizeof(Entry); }

 private:
  Vec2 lo_;              // world position of cell (0, 0)'s corner, m
  double cell_ = 1;      // m
  double inv_cell_ = 1;  // cells per m
  int nx_ = 0, ny_ = 0;
  // Cells row-major: start_[k]..start_[k + 1] indexes entries_ for cell k.
  std::vector<uint32_t> start_;
  std::vector<Entry> entries_;
  std::vector<uint32_t> cursor_;
};

template <class Visit>
void RobotLayer::walk(Vec2 o, Vec2 dir, double t_max, Visit&& visit) const {
  if (nx_ == 0) return;
  // Clip to the grid, in cell units.
  const double ox = (o.x - lo_.x) * inv_cell_, oy = (o.y - lo_.y) * inv_cell_;
  double t0 = 0, t1 = t_max * inv_cell_;
  const double org[2] = {ox, oy}, d[2] = {dir.x, dir.y}, hi[2] = {double(nx_), double(ny_)};
  for (int a = 0; a < 2; ++a) {
    if (d[a] == 0) {
      if (org[a] < 0 || org[a] >= hi[a]) return;
      continue;
    }
    double ta = -org[a] / d[a], tb = (hi[a] - org[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (!(t0 < t1)) return;
  // Amanatides-Woo from the clipped entry point.
  const double px = ox + t0 * dir.x, py = oy + t0 * dir.y;
  int ix = std::clamp(int(std::floor(px)), 0, nx_ - 1), iy = std::clamp(int(std::floor(py)), 0, ny_ - 1);
  const int step_x = dir.x >= 0 ? 1 : -1, step_y = dir.y >= 0 ? 1 : -1;
  constexpr double kFar = 1e300;
  const double delta_x = dir.x != 0 ? std::fabs(1 / dir.x) : kFar,
               delta_y = dir.y != 0 ? std::fabs(1 / dir.y) : kFar;
  double next_x = dir.x > 0 ? t0 + (ix + 1 - px) / dir.x : (dir.x < 0 ? t0 + (ix - px) / dir.x : kFar);
  double next_y = dir.y > 0 ? t0 + (iy + 1 - py) / dir.y : (dir.y < 0 ? t0 + (iy - py) / dir.y : kFar);
  double entry = t0;
  while (true) {
    const size_t k = size_t(iy) * size_t(nx_) + size_t(ix);
    const uint32_t b = start_[k], e = start_[k + 1];
    if (b != e) {
      const double limit = visit(std::span<const Entry>(entries_.data() + b, e - b), entry * cell_);
      t1 = std::min(t1, limit * inv_cell_);
    }
    if (next_x < next_y) {
      entry = next_x;
      next_x += delta_x;
      ix += step_x;
      if (ix < 0 || ix >= nx_) return;
    } else {
      entry = next_y;
      next_y += delta_y;
      iy += step_y;
      if (iy < 0 || iy >= ny_) return;
    }
    if (entry > t1) return;
  }
}

}  // namespace troupe::sim
