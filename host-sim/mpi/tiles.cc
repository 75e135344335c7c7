#include "host-sim/mpi/tiles.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace troupe::sim::mpi {
namespace {

// Cuts splitting `values` into `parts` runs of about equal length, each
// cut half way between the last value of one run and the first of the
// next. Sorts `values`.
std::vector<double> quantile_cuts(std::vector<double>& values, int parts) {
  std::vector<double> cuts;
  std::sort(values.begin(), values.end());
  for (int k = 1; k < parts; ++k) {
    if (values.empty()) {
      cuts.push_back(double(k));  // no robots: any increasing cuts do
      continue;
    }
    const size_t at = std::min(values.size() - 1, values.size() * size_t(k) / size_t(parts));
    const double below = at > 0 ? values[at - 1] : values[at];
    double cut = 0.5 * (below + values[at]);
    // Equal values on both sides leave an empty region; cuts must still
    // increase for owner() to be well defined.
    if (!cuts.empty() && cut <= cuts.back()) cut = std::nextafter(cuts.back(), INFINITY);
    cuts.push_back(cut);
  }
  return cuts;
}

// The same, each value weighing its cost: cut where the running cost
// passes k / parts of the whole. Sorts `points` (value, cost).
std::vector<double> weighted_cuts(std::vector<std::pair<double, double>>& points, int parts) {
  std::sort(points.begin(), points.end());
  double total = 0;
  for (const auto& p : points) total += p.second;
  std::vector<double> cuts;
  size_t at = 0;
  double below = 0;  // the cost of points[0, at)
  for (int k = 1; k < parts; ++k) {
    if (points.empty() || !(total > 0)) {
      cuts.push_back(double(k));  // nothing to weigh: any increasing cuts do
      continue;
    }
    const double want = total * double(k) / double(parts);
    while (at + 1 < points.size() && below + points[at].second < want) below += points[at++].second;
    const double before = at > 0 ? points[at - 1].first : points[at].first;
    double cut = 0.5 * (before + points[at].first);
    if (!cuts.empty() && cut <= cuts.back()) cut = std::nextafter(cuts.back(), INFINITY);
    cuts.push_back(cut);
  }
  return cuts;
}

// The index of the interval of `cuts` holding v: 0 below the first cut.
int interval(const std::vector<double>& cuts, double v) {
  return int(std::upper_bound(cuts.begin(), cuts.end(), v) - cuts.begin());
}

}  // namespace

Tiles Tiles::balanced(int ranks, std::span<const Vec2> points) {
  Tiles t;
  ranks = std::max(ranks, 1);
  t.rows_ = 1;
  for (int r = 1; r * r <= ranks; ++r) {
    if (ranks % r == 0) t.rows_ = r;
  }
  t.cols_ = ranks / t.rows_;
  std::vector<double> xs, ys;
  xs.reserve(points.size());
  ys.reserve(points.size());
  for (const Vec2& p : points) {
    xs.push_back(p.x);
    ys.push_back(p.y);
  }
  t.x_cuts_ = quantile_cuts(xs, t.cols_);
  t.y_cuts_ = quantile_cuts(ys, t.rows_);
  return t;
}

Tiles Tiles::balanced(int ranks, std::span<const Vec2> points, std::span<const double> costs) {
  Tiles t = balanced(ranks, {});
  std::vector<std::pair<double, double>> xs, ys;
  xs.reserve(points.size());
  ys.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const double c = i < costs.size() ? std::max(costs[i], 0.0) : 0.0;
    xs.push_back({points[i].x, c});
    ys.push_back({points[i].y, c});
  }
  t.x_cuts_ = weighted_cuts(xs, t.cols_);
  t.y_cuts_ = weighted_cuts(ys, t.rows_);
  return t;
}

int Tiles::owner(Vec2 p) const {
  return interval(y_cuts_, p.y) * cols_ + interval(x_cuts_, p.x);
}

void Tiles::region(int rank, Vec2& lo, Vec2& hi) const {
  const int c = rank % cols_, r = rank / cols_;
  lo = {c > 0 ? x_cuts_[size_t(c - 1)] : -INFINITY, r > 0 ? y_cuts_[size_t(r - 1)] : -INFINITY};
  hi = {c < cols_ - 1 ? x_cuts_[size_t(c)] : INFINITY, r < rows_ - 1 ? y_cuts_[size_t(r)] : INFINITY};
}

void Tiles::near(Vec2 p, double halo, std::vector<int>& out) const {
  out.clear();
  const int c0 = interval(x_cuts_, p.x - halo), c1 = interval(x_cuts_, p.x + halo);
  const int r0 = interval(y_cuts_, p.y - halo), r1 = interval(y_cuts_, p.y + halo);
  for (int r = r0; r <= r1; ++r) {
    for (int c = c0; c <= c1; ++c) out.push_back(r * cols_ + c);
  }
}

}  // namespace troupe::sim::mpi
