// Robots in a uniform grid, rebuilt every step by a counting sort into flat
// arrays: each robot sits in the one cell holding its centre, and a query
// widens its box by the largest robot radius, so no robot is listed twice.
// Robots outside the grid are kept in its border cells; queries clamp the
// same way, so nothing is missed.
//
// A grid with far more cells than robots (a campus-sized map with a thousand
// robots: 1.4 million cells) is kept sparse: the robots sorted by row, and
// in a row by column, and a query finds its columns in each row it spans by
// binary search, so a step's rebuild costs the robots, not the cells (it was
// over a third of such a world's step). Both keep the robots in the same order
// (row-major cells, a cell's robots by index), and a query visits the same
// ranges of it, so every result is the same whichever is used.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "host-sim/sim/geometry.h"

namespace troupe::sim {

class SpatialHash {
 public:
  /// A robot as the hash holds it: a copy of its circle, so queries that
  /// only filter by distance never touch the robots' own (scattered) data.
  struct Item {
    uint32_t index;  // the robot
    uint32_t flags;  // the caller's bits (e.g. visible to rangers)
    float x, y;      // circle centre, m
    float r;         // circle radius, m
  };

  /// Covers [lo, hi] with square cells of `cell` m.
  void reset(Vec2 lo, Vec2 hi, double cell);

  /// Rebuilds from the robots' centres and radii (m) and flag bits. Radius
  /// < 0 leaves a robot out.
  void build(const std::vector<Vec2>& centres, const std::vector<double>& radii,
             const std::vector<uint32_t>& flags);

  /// Calls visit(index) for every robot whose circle may touch the circle
  /// (c, r); the caller does the exact test. Each robot at most once.
  template <class Visit>
  void query(Vec2 c, double r, Visit&& visit) const {
    query_items(c, r, [&](const Item& it) { visit(it.index); });
  }
  /// The same, visiting the items (index, flags, circle).
  template <class Visit>
  void query_items(Vec2 c, double r, Visit&& visit) const {
    rows(c, r, [&](uint32_t begin, uint32_t end) {
      for (uint32_t i = begin; i < end; ++i) visit(items_[i]);
    });
  }

  /// How many robots query_items(c, r) would visit, counted from the
  /// cells' bounds alone (one read per row of cells, no robot touched).
  size_t count_items(Vec2 c, double r) const {
    size_t n = 0;
    rows(c, r, [&](uint32_t begin, uint32_t end) { n += end - begin; });
    return n;
  }

  /// Every robot in the hash, cell by cell (row-major): an order in which
  /// consecutive robots are near each other.
  std::span<const Item> order() const { return items_; }

  double max_radius() const { return max_radius_; }
  size_t memory_bytes() const {
    return (start_.capacity() + cell_of_.capacity() + scratch_.capacity() + row_start_.capacity() +
            item_x_.capacity() + by_column_.capacity()) *
               4 +
           items_.capacity() * sizeof(Item);
  }
  /// Whether the last build() kept the grid sparse.
  bool sparse() const { return sparse_; }

  /// A grid with more cells than this per robot is kept sparse.
  static constexpr size_t kSparseCellsPerRobot = 64;
  /// Tests only: keep the grid dense or sparse whatever its size (Auto: by
  /// kSparseCellsPerRobot). Results are the same either way.
  enum class Storage { Auto, Dense, Sparse };
  void set_storage(Storage storage) { storage_ = storage; }

 private:
  // Calls row(begin, end) with the range of items_ of each row of cells
  // that the circle (c, r), widened by the largest radius, overlaps.
  template <class Row>
  void rows(Vec2 c, double r, Row&& row) const {
    const double reach = r + max_radius_;
    const int x0 = cell_x(c.x - reach), x1 = cell_x(c.x + reach);
    const int y0 = cell_y(c.y - reach), y1 = cell_y(c.y + reach);
    if (sparse_) {
      for (int y = y0; y <= y1; ++y) {
        const uint32_t* first = item_x_.data() + row_start_[size_t(y)];
        const uint32_t* last = item_x_.data() + row_start_[size_t(y) + 1];
        const uint32_t* b = std::lower_bound(first, last, uint32_t(x0));
        const uint32_t* e = std::upper_bound(b, last, uint32_t(x1));
        row(uint32_t(b - item_x_.data()), uint32_t(e - item_x_.data()));
      }
      return;
    }
    for (int y = y0; y <= y1; ++y) {
      const uint32_t* cells = &start_[size_t(y) * size_t(nx_)];
      row(cells[x0], cells[x1 + 1]);
    }
  }
  void build_dense(const std::vector<Vec2>& centres, const std::vector<double>& radii,
                   const std::vector<uint32_t>& flags);
  void build_sparse(const std::vector<Vec2>& centres, const std::vector<double>& radii,
                    const std::vector<uint32_t>& flags);
  int cell_x(double x) const { return std::clamp(int(std::floor((x - lo_.x) * inv_cell_)), 0, nx_ - 1); }
  int cell_y(double y) const { return std::clamp(int(std::floor((y - lo_.y) * inv_cell_)), 0, ny_ - 1); }

  Vec2 lo_;
  double inv_cell_ = 1;
  int nx_ = 1, ny_ = 1;
  double max_radius_ = 0;
  // Cells in row-major order; start_[k]..start_[k+1] indexes items_ for
  // cell k. Rows are contiguous, so a row's span of cells is one range.
  // Dense only: start_ as above.
  std::vector<uint32_t> start_;
  std::vector<Item> items_;
  std::vector<uint32_t> cell_of_;  // per robot: its cell (dense) or its column (sparse)
  std::vector<uint32_t> scratch_;
  // Sparse only: row y's robots are items_[row_start_[y] .. row_start_[y + 1]),
  // item_x_ the column of each item (ascending within a row), and by_column_
  // the robots ordered by column, the first pass of the sort.
  bool sparse_ = false;
  Storage storage_ = Storage::Auto;
  std::vector<uint32_t> row_start_;
  std::vector<uint32_t> item_x_;
  std::vector<uint32_t> by_column_;
};

}  // namespace troupe::sim
