// A world's floor cut into regions, one per process: `cols` x `rows`
// rectangles whose x cuts are shared by every row and y cuts by every
// column, so four regions meet at each inner corner. The outer regions
// reach to infinity: every point has one owner.
#pragma once

#include <span>
#include <vector>

#include "host-sim/sim/geometry.h"

namespace troupe::sim::mpi {

class Tiles {
 public:
  /// `ranks` regions (>= 1), cut so each column and each row holds about
  /// as many of `points` (world frame, m) as the others: the robots'
  /// centres, so each process steps about as many robots. Columns >= rows,
  /// as square as `ranks` allows (2: 2 x 1, 4: 2 x 2, 6: 3 x 2).
  static Tiles balanced(int ranks, std::span<const Vec2> points);
  /// The same with a cost for each point (any unit, >= 0; as many as
  /// points): each column and row holds about as much cost as the others.
  /// A process's measured step time spread over its robots makes regions
  /// of about equal step time where robots' costs differ (a crowd's
  /// rangers see more robots than lone ones do).
  static Tiles balanced(int ranks, std::span<const Vec2> points, std::span<const double> costs);

  int ranks() const { return cols_ * rows_; }
  int cols() const { return cols_; }
  int rows() const { return rows_; }
  /// The cuts, m, ascending: cols() - 1 in x, rows() - 1 in y.
  const std::vector<double>& x_cuts() const { return x_cuts_; }
  const std::vector<double>& y_cuts() const { return y_cuts_; }

  /// The rank whose region holds `p` (a point on a cut belongs to the
  /// region above it).
  int owner(Vec2 p) const;
  /// Rank `rank`'s region, [lo, hi) (m; infinite on the outer sides).
  void region(int rank, Vec2& lo, Vec2& hi) const;
  /// Every rank whose region, grown by `halo` m on every side, holds `p`,
  /// ascending, into `out` (cleared first). The owner is among them.
  void near(Vec2 p, double halo, std::vector<int>& out) const;

 private:
  int cols_ = 1, rows_ = 1;
  std::vector<double> x_cuts_, y_cuts_;
};

}  // namespace troupe::sim::mpi
