// The likelihood-field laser model (Thrun et al., "Probabilistic Robotics",
// 6.4): a beam's endpoint is likely when it lands near an obstacle. The
// distance to the nearest occupied cell is computed once for the whole map
// (an exact Euclidean distance transform), and the log-likelihood of an
// endpoint in each cell is stored, so a beam costs one table lookup.
#pragma once

#include <vector>

#include "drivers/common_desktop/occupancy_grid.h"

namespace troupe::desktop {

struct LikelihoodFieldParams {
  /// Standard deviation of the range error around an obstacle, m.
  double sigma_hit = 0.2;
  /// Mixture weights: a hit near an obstacle, and a uniformly random
  /// reading over [0, max_range). z_hit + z_rand should be 1.
  double z_hit = 0.95;
  double z_rand = 0.05;
  /// The range a random reading is spread over (the laser's useful range), m.
  double max_range = 30.0;
  /// Distances beyond this count as this far: the Gaussian is negligible
  /// there and the transform stays cheap, m.
  double max_distance = 2.0;
  /// Distances are measured to the surface between occupied and free
  /// cells, from both sides: an endpoint inside an obstacle counts its depth.
  /// Off (the classic field: centre to centre, 0 anywhere inside), every
  /// cell of a thick wall is a perfect hit and a beam ending in the wall cell
  /// beats one ending in front of it, so the belief slides towards the walls
  /// the laser faces: a bias along the direction of travel (bench_mcl_sim:
  /// 6 cm with 0.2 m walls on a 0.05 m map, 0.7 cm with the surface field).
  /// Maps drawn from scan endpoints (one-cell walls, the ACES log) gain
  /// nothing and lose a little sharpness, so the classic field stays the
  /// default.
  bool surface = false;
};

class LikelihoodField {
 public:
  LikelihoodField() = default;
  /// Computes distances and log-likelihoods for every cell of `map`.
  LikelihoodField(const OccupancyGrid& map, const LikelihoodFieldParams& params);

  /// The likelihood density of a beam ending at map point (x, y) (m), 1/m:
  /// z_hit * N(d; 0, sigma_hit) + z_rand / max_range, with d the distance
  /// from the endpoint's cell centre to the nearest occupied cell centre
  /// (with `surface`: to the obstacle's surface, see above).
  double likelihood(double x, double y) const { return std::exp(double(log_likelihood(x, y))); }
  /// Its natural logarithm: what the filter sums over beams.
  float log_likelihood(double x, double y) const {
    int64_t c = 0, r = 0;
    map_->world_to_cell(x, y, c, r);
    return map_->contains(c, r) ? log_p_[size_t(r) * map_->width() + size_t(c)] : log_p_far_;
  }
  /// The same for a cell given by its indices (any, on the map or not).
  float cell_log_likelihood(int64_t col, int64_t row) const {
    return map_->contains(col, row) ? log_p_[size_t(row) * map_->width() + size_t(col)] : log_p_far_;
  }
  /// Distance from the centre of (col, row) to the nearest occupied cell
  /// centre, capped at max_distance, m.
  double distance(uint32_t col, uint32_t row) const;

  const LikelihoodFieldParams& params() const { return params_; }
  /// The log-likelihood of an endpoint at max_distance or off the map.
  float log_likelihood_far() const { return log_p_far_; }

 private:
  const OccupancyGrid* map_ = nullptr;
  LikelihoodFieldParams params_;
  std::vector<float> dist_;   // m, per cell
  std::vector<float> log_p_;  // per cell
  float log_p_far_ = 0;
};

/// The same mixture for one distance, m -> 1/m (tests compare against it).
double likelihood_of_distance(double distance_m, const LikelihoodFieldParams& params);

/// Squared Euclidean distance, in cells^2, from every cell to the nearest
/// cell for which `is_site` holds (Felzenszwalb and Huttenlocher's exact
/// transform, two passes of the 1-D lower envelope). Cells farther than
/// `cap_cells` get cap_cells^2.
std::vector<float> squared_distance_transform(const OccupancyGrid& map, CellState site, double cap_cells);

}  // namespace troupe::desktop
