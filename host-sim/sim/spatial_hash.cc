#include "host-sim/sim/spatial_hash.h"

namespace troupe::sim {

void SpatialHash::reset(Vec2 lo, Vec2 hi, double cell) {
  lo_ = lo;
  inv_cell_ = 1.0 / cell;
  nx_ = std::max(1, int(std::ceil((hi.x - lo.x) * inv_cell_)));
  ny_ = std::max(1, int(std::ceil((hi.y - lo.y) * inv_cell_)));
  // The cells' table is made by the first dense build: a sparse grid never
  // needs it.
  start_.clear();
  start_.shrink_to_fit();
  items_.clear();
  item_x_.clear();
  row_start_.assign(size_t(ny_) + 1, 0);
  sparse_ = false;
}

void SpatialHash::build(const std::vector<Vec2>& centres, const std::vector<double>& radii,
                        const std::vector<uint32_t>& flags) {
  const size_t cells = size_t(nx_) * size_t(ny_);
  sparse_ = storage_ == Storage::Auto ? cells > kSparseCellsPerRobot * std::max<size_t>(centres.size(), 1)
                                      : storage_ == Storage::Sparse;
  max_radius_ = 0;
  for (size_t i = 0; i < centres.size(); ++i) {
    if (radii[i] >= 0) max_radius_ = std::max(max_radius_, radii[i]);
  }
  if (sparse_) {
    build_sparse(centres, radii, flags);
  } else {
    build_dense(centres, radii, flags);
  }
}

void SpatialHash::build_dense(const std::vector<Vec2>& centres, const std::vector<double>& radii,
                              const std::vector<uint32_t>& flags) {
  const size_t n = centres.size(), cells = size_t(nx_) * size_t(ny_);
  cell_of_.resize(n);
  if (start_.size() != cells + 1) {
    start_.assign(cells + 1, 0);
  } else {
    std::fill(start_.begin(), start_.end(), 0u);
  }
  uint32_t count = 0;
  for (size_t i = 0; i < n; ++i) {
    if (radii[i] < 0) {
      cell_of_[i] = uint32_t(cells);
      continue;
    }
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

void SpatialHash::build_sparse(const std::vector<Vec2>& centres, const std::vector<double>& radii,
                               const std::vector<uint32_t>& flags) {
  // Two stable counting sorts, by column and then by row, give the dense
  // grid's order (row-major cells, each cell's robots by index) in time
  // proportional to the robots plus one row and one column of cells.
  const size_t n = centres.size();
  const uint32_t left_out = uint32_t(nx_);
  cell_of_.resize(n);
  std::vector<uint32_t>& columns = scratch_;
  columns.assign(size_t(nx_) + 1, 0);
  row_start_.assign(size_t(ny_) + 1, 0);
  uint32_t count = 0;
  for (size_t i = 0; i < n; ++i) {
    if (radii[i] < 0) {
      cell_of_[i] = left_out;
      continue;
    }
    const uint32_t x = uint32_t(cell_x(centres[i].x));
    cell_of_[i] = x;
    ++columns[x + 1];
    ++row_start_[size_t(cell_y(centres[i].y)) + 1];
    ++count;
  }
  for (size_t x = 1; x < columns.size(); ++x) columns[x] += columns[x - 1];
  for (size_t y = 1; y < row_start_.size(); ++y) row_start_[y] += row_start_[y - 1];
  by_column_.resize(count);
  for (size_t i = 0; i < n; ++i) {
    if (cell_of_[i] != left_out) by_column_[columns[cell_of_[i]]++] = uint32_t(i);
  }
  items_.resize(count);
  item_x_.resize(count);
  // The row cursors reuse the columns' array, which is done with.
  std::vector<uint32_t>& cursor = scratch_;
  cursor.assign(row_start_.begin(), row_start_.end() - 1);
  for (uint32_t i : by_column_) {
    const uint32_t at = cursor[size_t(cell_y(centres[i].y))]++;
    items_[at] = {i, flags[i], float(centres[i].x), float(centres[i].y), float(radii[i])};
    item_x_[at] = cell_of_[i];
  }
}

}  // namespace troupe::sim
