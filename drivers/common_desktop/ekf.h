// An extended Kalman filter for a planar base: the algorithm of the fusion
// driver. State (x, y, heading, forward speed, turn rate) in the map frame:
// m, m, rad, m/s, rad/s, with a constant-velocity motion model whose speeds
// wander as white-noise accelerations.
//
// Measurements: odometry (as the speed and turn rate between consecutive
// odometry poses), a gyro's yaw rate, absolute pose fixes (a localizer's
// estimate) and landmark sightings (a fiducial at a known map pose, seen
// relative to the robot). Every measurement carries its timestamp. The
// filter keeps the last `history_s` seconds of measurements with the state
// after each, so a fix that arrives late, or out of order, is inserted at
// its own time and everything after it is filtered again.
#pragma once

#include <Eigen/Core>
#include <deque>

#include "drivers/common_desktop/pose2.h"

namespace troupe::desktop {

struct EkfParams {
  /// Random-walk strength of the speeds: acceleration spectral densities,
  /// (m/s^2)^2 per Hz and (rad/s^2)^2 per Hz.
  double accel_psd = 0.5;
  double turn_accel_psd = 1.0;
  /// Extra pose diffusion per second (wheel slip the model has no term
  /// for): m^2/s, rad^2/s.
  double pose_psd_xy = 1e-4;
  double pose_psd_a = 1e-5;
  /// Odometry noise on the speeds derived from it: m/s, rad/s.
  double odom_speed_sigma = 0.05;
  double odom_turn_sigma = 0.05;
  /// Measurements older than the newest by more than this are dropped, s.
  double history_s = 2.0;
  /// Mahalanobis gate for fixes and landmarks (chi-square, 3 dof): an
  /// innovation beyond it is refused as an outlier. 0: no gate. After
  /// `max_gated` refusals in a row the filter trusts the fix again (the
  /// localizer has recovered, the filter is the one that is lost).
  double gate = 16.27;  // 99.9% for 3 dof
  int max_gated = 5;
};

class PoseEkf {
 public:
  using State = Eigen::Matrix<double, 5, 1>;
  using Cov = Eigen::Matrix<double, 5, 5>;

  enum class Outcome : uint8_t {
    Applied,      // in time order
    AppliedLate,  // inserted into the past and the states after it re-filtered
    TooOld,       // older than the history: dropped
    Gated,        // refused as an outlier
    NotReady,     // no pose yet (waiting for the first fix or reset())
    Invalid,      // not finite, or a covariance that is not positive
  };

  explicit PoseEkf(const EkfParams& params) : params_(params) {}

  /// Starts at `pose` (m, m, rad) with covariance `cov` at `time_s`, speeds
  /// zero (with a generous variance). Forgets the history.
  void reset(double time_s, const Pose2& pose, const Eigen::Matrix3d& cov);
  bool ready() const { return !history_.empty(); }

  /// An odometry pose (m, m, rad, in the odometry frame) at `time_s`. The
  /// first one only starts the next interval. Odometry comes in order.
  Outcome add_odometry(double time_s, const Pose2& odom);
  /// A gyro's yaw rate, rad/s, with its standard deviation, rad/s.
  Outcome add_yaw_rate(double time_s, double rate, double sigma);
  /// An absolute pose (map frame) with its covariance (m^2, rad^2). Before
  /// the filter is ready the first fix starts it.
  Outcome add_pose_fix(double time_s, const Pose2& pose, const Eigen::Matrix3d& cov);
  /// A landmark whose map pose is `landmark`, seen at `seen` relative to the
  /// robot (m forward, m left, rad) with covariance `cov`.
  Outcome add_landmark(double time_s, const Pose2& landmark, const Pose2& seen, const Eigen::Matrix3d& cov);

  /// The newest state and covariance, and their time, s.
  const State& state() const { return history_.back().x; }
  const Cov& covariance() const { return history_.back().p; }
  double time_s() const { return history_.back().time_s; }
  Pose2 pose() const { return {state()(0), state()(1), state()(2)}; }
  /// The state predicted forward to `time_s` (not stored).
  void predict_to(double time_s, State& x, Cov& p) const;

  size_t late_count() const { return late_; }
  size_t dropped_count() const { return dropped_; }
  size_t gated_count() const { return gated_total_; }

 private:
  enum class Kind : uint8_t { Start, Speeds, YawRate, Pose, Landmark };
  struct Measurement {
    Kind kind = Kind::Start;
    Eigen::Vector3d z = Eigen::Vector3d::Zero();
    Eigen::Matrix3d r = Eigen::Matrix3d::Zero();
    Pose2 landmark;
  };
  // A measurement and the state right after it was applied.
  struct Entry {
    double time_s = 0;
    Measurement m;
    State x;
    Cov p;
    bool accepted = true;  // false: kept for order, but gated (not applied)
  };

  Outcome add(double time_s, const Measurement& m);
  void predict(double dt, State& x, Cov& p) const;
  // Applies m to (x, p); false when gated.
  bool correct(const Measurement& m, State& x, Cov& p, bool gate);
  void prune();

  EkfParams params_;
  std::deque<Entry> history_;  // time order; front() is the base state
  bool has_odom_ = false;
  double odom_time_s_ = 0;
  Pose2 last_odom_;
  int gated_in_row_ = 0;
  size_t late_ = 0, dropped_ = 0, gated_total_ = 0;
};

}  // namespace troupe::desktop
