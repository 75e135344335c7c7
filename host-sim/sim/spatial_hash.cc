#include "host-sim/sim/spatial_hash.h"

namespace troupe::sim {

void SpatialHash::reset(Vec2 lo, Vec2 hi, double cell) {
  lo_ = lo;
  inv_cell_ = 1.0 / cell;
  nx_ = std::max(1, int(std::ceil((hi.x - lo.x) * inv_cell_)));
  ny_ = std::max(1, int(std::ceil((hi.y - lo.y) * inv_cell_)));
  start_.assign(size_t(nx_) * size_t(ny_) + 1, 0);
  items_.clear();
}

void SpatialHash::build(const std::vector<Vec2>& centres, const std::vector<double>& radii,
                        const std::vector<uint32_t>& flags) {
  const size_t n = centres.size(), cells = size_t(nx_) * size_t(ny_);
  cell_of_.resize(n);
  std::fill(start_.begin(), start_.end(), 0u);
  max_radius_ = 0;
  uint32_t count = 0;
  for (size_t i = 0; i < n; ++i) {
    if (radii[i] < 0) {
      cell_of_[i] = uint32_t(cells);
      continue;
    }
    max_radius_ = std::max(max_radius_, radii[i]);
    uint32_t k = uint32_t(size_t(cell_y(centres[i].y)) * size_t(nx_) + size_t(cell_x(centres[i].x)));
    cell_of_[i] = k;
    ++start_[k + 1];
    ++count;
  }
  for (size_t k = 1; k <= cells; ++k) start_[k] += start_[k - 1];
  items_.resize(count);
  // Fill in index order through a cursor per cell (start_ shifted by one),
  // so the order inside a cell is the robots' order: deterministic.
  std::vector<uint32_t>& cursor = scratch_;
  cursor.assign(start_.begin(), start_.end() - 1);
  for (size_t i = 0; i < n; ++i) {
    uint32_t k = cell_of_[i];
    if (k < cells) {
      items_[cursor[k]++] = {uint32_t(i), flags[i], float(centres[i].x), float(centres[i].y),
                             float(radii[i])};
    }
  }
}

}  // namespace troupe::sim
