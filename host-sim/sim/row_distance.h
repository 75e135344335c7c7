// Exact squared distances along one row of a grid, given each column's
// squared vertical distance to its nearest obstacle: the lower envelope of
// parabolas of Felzenszwalb and Huttenlocher's distance transform. The
// dense map runs it on every row of cells, the sparse map on every row of
// blocks; the arithmetic is exact for grids of this size (the parabolas'
// crossings are at least 1 / (2 * width) from a whole column unless they
// are on one, where either parabola gives the same distance).
#pragma once

#include <limits>
#include <vector>

namespace troupe::sim {

class RowDistance {
 public:
  /// Builds the envelope of `n` columns; f[x] is column x's squared
  /// vertical distance, cells^2.
  void build(const double* f, int n) {
    f_ = f;
    v_.resize(size_t(n));
    z_.resize(size_t(n) + 1);
    int k = 0;
    v_[0] = 0;
    z_[0] = -std::numeric_limits<double>::infinity();
    z_[1] = std::numeric_limits<double>::infinity();
    for (int q = 1; q < n; ++q) {
      // z[0] is -infinity, so k never drops below 0.
      auto cut = [&](int p) { return ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * (q - p)); };
      double s = cut(v_[size_t(k)]);
      while (s <= z_[size_t(k)]) {
        --k;
        s = cut(v_[size_t(k)]);
      }
      ++k;
      v_[size_t(k)] = q;
      z_[size_t(k)] = s;
      z_[size_t(k) + 1] = std::numeric_limits<double>::infinity();
    }
    k_ = 0;
  }
  /// Column q's squared distance to the nearest obstacle, cells^2. Columns
  /// are asked for in increasing order.
  double at(int q) {
    while (z_[size_t(k_) + 1] < q) ++k_;
    const int p = v_[size_t(k_)];
    return double(q - p) * (q - p) + f_[p];
  }

 private:
  const double* f_ = nullptr;
  std::vector<int> v_;
  std::vector<double> z_;
  int k_ = 0;
};

}  // namespace troupe::sim
