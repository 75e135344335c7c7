#include "drivers/common_desktop/likelihood_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace troupe::desktop {
namespace {

// 1-D squared distance transform of f (size n) into d: the lower envelope of
// the parabolas (q - p)^2 + f[p]. Cells without a site hold kFar, which is
// finite so that the intersection arithmetic needs no special cases.
constexpr double kFar = 1e30;

void transform_1d(const double* f, size_t n, double* d, std::vector<int>& v, std::vector<double>& z) {
  int k = 0;
  v[0] = 0;
  z[0] = -std::numeric_limits<double>::infinity();
  z[1] = std::numeric_limits<double>::infinity();
  for (int q = 1; q < int(n); ++q) {
    double s = 0;
    while (true) {
      int p = v[k];
      s = ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / double(2 * q - 2 * p);
      if (s > z[k]) break;
      --k;
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = std::numeric_limits<double>::infinity();
  }
  k = 0;
  for (int q = 0; q < int(n); ++q) {
    while (z[k + 1] < double(q)) ++k;
    double dq = double(q - v[k]);
    d[q] = dq * dq + f[v[k]];
  }
}

}  // namespace

std::vector<float> squared_distance_transform(const OccupancyGrid& map, CellState site, double cap_cells) {
  const size_t w = map.width(), h = map.height();
  std::vector<double> grid(w * h);
  for (size_t i = 0; i < grid.size(); ++i) grid[i] = map.cells()[i] == uint8_t(site) ? 0.0 : kFar;
  size_t longest = std::max(w, h);
  std::vector<double> f(longest), d(longest), z(longest + 1);
  std::vector<int> v(longest);
  // Columns first, then rows.
  for (size_t c = 0; c < w; ++c) {
    for (size_t r = 0; r < h; ++r) f[r] = grid[r * w + c];
    transform_1d(f.data(), h, d.data(), v, z);
    for (size_t r = 0; r < h; ++r) grid[r * w + c] = d[r];
  }
  for (size_t r = 0; r < h; ++r) {
    std::copy(grid.begin() + long(r * w), grid.begin() + long((r + 1) * w), f.begin());
    transform_1d(f.data(), w, d.data(), v, z);
    std::copy(d.begin(), d.begin() + long(w), grid.begin() + long(r * w));
  }
  double cap2 = cap_cells * cap_cells;
  std::vector<float> out(grid.size());
  for (size_t i = 0; i < grid.size(); ++i) out[i] = float(std::min(grid[i], cap2));
  return out;
}

double likelihood_of_distance(double d, const LikelihoodFieldParams& p) {
  double gauss = std::exp(-0.5 * d * d / (p.sigma_hit * p.sigma_hit)) / (std::sqrt(2 * kPi) * p.sigma_hit);
  return p.z_hit * gauss + p.z_rand / p.max_range;
}

LikelihoodField::LikelihoodField(const OccupancyGrid& map, const LikelihoodFieldParams& params)
    : map_(&map), params_(params) {
  double cap_cells = params.max_distance / map.resolution();
  std::vector<float> d2 = squared_distance_transform(map, CellState::Occupied, cap_cells);
  if (params.surface) {
    // Distances to the surface between occupied and free space, from either
    // side: half a cell less than centre to centre outside an obstacle, and
    // inside it, the distance to the nearest free cell less half a cell.
    std::vector<float> to_free = squared_distance_transform(map, CellState::Free, cap_cells + 1);
    const double cap2 = cap_cells * cap_cells;
    for (size_t i = 0; i < d2.size(); ++i) {
      bool inside = map.cells()[i] == uint8_t(CellState::Occupied);
      double d = std::max(0.0, std::sqrt(double(inside ? to_free[i] : d2[i])) - 0.5);
      d2[i] = float(std::min(d * d, cap2));
    }
  }
  dist_.resize(d2.size());
  log_p_.resize(d2.size());
  for (size_t i = 0; i < d2.size(); ++i) {
    dist_[i] = float(std::sqrt(double(d2[i])) * map.resolution());
    log_p_[i] = float(std::log(likelihood_of_distance(dist_[i], params)));
  }
  log_p_far_ = float(std::log(likelihood_of_distance(params.max_distance, params)));
}

double LikelihoodField::distance(uint32_t col, uint32_t row) const {
  return dist_[size_t(row) * map_->width() + col];
}

}  // namespace troupe::desktop
