#include "host-sim/sim/robot_layer.h"

#include <algorithm>

namespace troupe::sim {
namespace {

// The hash keeps circles in floats: its radii grow by this much (m) to hold
// the robot still, as the rangers' candidate test does.
constexpr double kFloatPad = 1e-3;

}  // namespace

void RobotLayer::build(const SpatialHash& hash, uint32_t flags) {
  const std::span<const SpatialHash::Item> items = hash.order();
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300, max_r = 0;
  size_t n = 0;
  for (const SpatialHash::Item& it : items) {
    if (!(it.flags & flags)) continue;
    const double r = double(it.r) + kFloatPad;
    x0 = std::min(x0, it.x - r);
    y0 = std::min(y0, it.y - r);
    x1 = std::max(x1, it.x + r);
    y1 = std::max(y1, it.y + r);
    max_r = std::max(max_r, r);
    ++n;
  }
  entries_.clear();
  if (n == 0) {
    nx_ = ny_ = 0;
    return;
  }
  // Cells three quarters of the widest robot circle wide: a robot is listed
  // in four to nine, a cell lists a few. Half and whole widths measured the
  // same on the packed row (callgrind). Wider when the robots are spread so
  // far apart that such cells would outnumber them by far.
  const double w = x1 - x0, h = y1 - y0;
  cell_ = std::max({1.5 * max_r, std::sqrt(w * h / (4.0 * double(n) + 64)), 1e-3});
  inv_cell_ = 1 / cell_;
  nx_ = std::max(1, int(std::ceil(w * inv_cell_)));
  ny_ = std::max(1, int(std::ceil(h * inv_cell_)));
  lo_ = {x0, y0};
  // A circle is listed in every cell its bounding square overlaps, grown by
  // a hair so a ray the walk passes from one cell to a diagonal neighbour
  // through their shared corner (rounding) still finds what it touched.
  const double hair = 1e-6 * cell_;
  auto range = [&](double c, double r, int cells, int& a, int& b) {
    a = std::clamp(int(std::floor((c - r - hair) * inv_cell_)), 0, cells - 1);
    b = std::clamp(int(std::floor((c + r + hair) * inv_cell_)), 0, cells - 1);
  };
  // Counting sort into cells: count, prefix sums, fill in the hash's order.
  start_.assign(size_t(nx_) * size_t(ny_) + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    for (uint32_t p = 0; p < items.size(); ++p) {
      const SpatialHash::Item& it = items[p];
      if (!(it.flags & flags)) continue;
      const double r = double(it.r) + kFloatPad;
      int ax, bx, ay, by;
      range(it.x - lo_.x, r, nx_, ax, bx);
      range(it.y - lo_.y, r, ny_, ay, by);
      for (int y = ay; y <= by; ++y) {
        for (int x = ax; x <= bx; ++x) {
          const size_t k = size_t(y) * size_t(nx_) + size_t(x);
          if (pass == 0) {
            ++start_[k + 1];
          } else {
            entries_[cursor_[k]++] = {it.index, p, it.x, it.y, float(r)};
          }
        }
      }
    }
    if (pass == 0) {
      for (size_t k = 1; k < start_.size(); ++k) start_[k] += start_[k - 1];
      entries_.resize(start_.back());
      cursor_.assign(start_.begin(), start_.end() - 1);
    }
  }
}

}  // namespace troupe::sim
