// A perceptual model for Monte Carlo localization from landmark features
// (a RoboCup field's goals and posts): an expectation table learned in the
// simulator, and a Gaussian sensor model on top of it.
//
// The table holds, for every pose of a grid (x, y, heading), where each
// landmark appears in the sensor's frame, or that it is not seen from
// there. The RoboCup player plugin `landmark_learner` makes it by placing
// its robot on every pose of the grid and recording what its sensor
// reports. At run time the expectation at a particle's pose is
// interpolated: bilinearly over the four surrounding positions at the
// nearest grid heading (at a fixed heading a landmark's position in the
// robot frame is affine in the robot's position, so this is exact where
// the four agree on seeing it), then rotated by the difference between the
// grid heading and the particle's (exact for a sensor at the robot's
// centre, such as an omni-directional camera).
//
// File format (text, one record a line):
//   troupe-landmarks 2
//   grid X0 Y0 STEP NX NY HEADINGS     m, m, m, counts; headings 2 pi / HEADINGS apart from 0
//   landmarks N K1:I1 ... KN:IN         fiducial kind (lower case, as in
//                                       wire/schemas/fiducial.fbs) and id: "goal:1 post:4"
//   then NX * NY * HEADINGS lines, heading-major, then row (y), then column
//   (x): N pairs "X Y" (sensor frame, m), "nan nan" where not seen.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "drivers/common_desktop/particle_filter.h"
#include "wire/fiducial_key.h"

namespace troupe::desktop {

/// A landmark's identity as a fiducial device reports it.
using LandmarkKey = wire::FiducialKey;

class LandmarkTable {
 public:
  /// Reads a table; false with `error` naming the file, line and problem.
  bool load(const std::string& path, std::string& error);
  /// Reads a table from text (`name` for messages).
  bool parse(const std::string& text, const std::string& name, std::string& error);

  /// The column of a landmark, -1 when the table does not know it.
  int column(const LandmarkKey& key) const;
  /// The expected position (sensor frame, m) of column `k` seen from
  /// `pose` (map frame: m, m, rad); false when it is not expected to be
  /// seen, or the pose is off the grid.
  bool expected(const Pose2& pose, int k, double& x, double& y) const;

  size_t landmarks() const { return keys_.size(); }
  /// The grid's corners, m: the area the table covers.
  double min_x() const { return x0_; }
  double min_y() const { return y0_; }
  double max_x() const { return x0_ + step_ * (nx_ - 1); }
  double max_y() const { return y0_ + step_ * (ny_ - 1); }
  size_t poses() const { return size_t(nx_) * size_t(ny_) * size_t(headings_); }

 private:
  /// Sensor-frame position of column k from grid node (ix, iy, ia).
  const float* at(int ix, int iy, int ia, int k) const {
    return &cells_[((size_t(ia) * size_t(ny_) + size_t(iy)) * size_t(nx_) + size_t(ix)) * keys_.size() * 2 +
                   size_t(k) * 2];
  }

  double x0_ = 0, y0_ = 0, step_ = 1;
  int nx_ = 0, ny_ = 0, headings_ = 0;
  std::vector<LandmarkKey> keys_;
  std::vector<float> cells_;
};

/// One landmark observed: what it is and its position in the sensor frame, m.
struct LandmarkObservation {
  LandmarkKey key;
  double x = 0, y = 0;
};

struct LandmarkModelParams {
  /// Range error: sigma = sigma_distance + sigma_distance_per_m * range, m.
  double sigma_distance = 0.1;
  double sigma_distance_per_m = 0.05;
  /// Bearing error, rad.
  double sigma_bearing = 0.08;
  /// Log-likelihood of a landmark seen where the table expects it unseen
  /// (or off the grid): as unlikely as a 3-sigma error on both.
  double log_unexpected = -9.0;
};

/// The Gaussian sensor model on distance and bearing over the table.
class LandmarkLikelihood final : public PoseLikelihood {
 public:
  LandmarkLikelihood(const LandmarkTable& table, const LandmarkModelParams& params)
      : table_(table), params_(params) {}

  /// This instant's observations; landmarks the table does not know are left out.
  void set(std::span<const LandmarkObservation> observations);

  double log_likelihood(const Pose2& pose) const override;
  size_t terms() const override { return used_.size(); }

 private:
  struct Used {
    int column;
    double distance, bearing;  // m, rad
  };
  const LandmarkTable& table_;
  LandmarkModelParams params_;
  std::vector<Used> used_;
};

}  // namespace troupe::desktop
