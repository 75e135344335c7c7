// Adaptive Monte Carlo localization against an occupancy map: the algorithm
// behind the mcl driver and troupe-mcl-eval. It knows nothing of nodes or
// sockets: feed it odometry poses and laser scans, read hypotheses back.
//
//  - motion: the differential-drive odometry model (motion_model.h);
//  - sensor: the likelihood field (likelihood_field.h) over a subset of the
//    beams, in log space;
//  - resampling: low-variance (one random offset, evenly spaced pointers),
//    visiting the pointers in van der Corput order so that any prefix of the
//    new set is itself evenly spread. That lets KLD sampling (Fox 2003) stop
//    as soon as the set is large enough for the bins it covers, between
//    min_particles and max_particles;
//  - lost detection: augmented MCL's short- and long-term averages of the
//    measurement likelihood (w_fast, w_slow). The filter says it is lost
//    while w_fast < lost_ratio * w_slow; the long-term average stops
//    learning then, so a filter that stays lost keeps saying so (and keeps
//    recovering) instead of getting used to it;
//  - recovery: while lost, a share 1 - w_fast/w_slow of the new particles is
//    injected: the poses among recovery_candidates uniform free-space draws
//    that explain the current scan best (sensor resetting), or with
//    recovery_candidates 0 the uniform draws themselves (classic augmented
//    MCL). drivers/mcl/README.md has the measurements behind the choice;
//  - global localization: particles uniform over the free cells; pose
//    tracking: particles drawn from a Gaussian around a given pose.
#pragma once

#include <Eigen/Core>
#include <span>
#include <unordered_set>
#include <vector>

#include "drivers/common_desktop/likelihood_field.h"
#include "drivers/common_desktop/motion_model.h"
#include "drivers/common_desktop/rng.h"

namespace troupe::desktop {

struct MclParams {
  size_t min_particles = 500;
  size_t max_particles = 5000;
  /// Particles of a global initialisation. Finding a pose in a large map
  /// takes a sample near it; the first resampling shrinks the set to within
  /// [min_particles, max_particles] at once.
  size_t global_particles = 50000;
  /// KLD sampling: the bound on the K-L divergence between the sample-based
  /// and the true posterior (epsilon), and the upper standard normal
  /// quantile of the confidence 1 - delta (2.326 for delta = 0.01).
  double kld_error = 0.02;
  double kld_z = 2.326;
  /// KLD histogram bin size: m, rad. Also the grid particles are clustered on.
  double bin_xy = 0.5;
  double bin_a = 10 * kPi / 180;
  MotionNoise motion;
  LikelihoodFieldParams sensor;
  /// Beams used per scan, evenly spaced over the scan (the rest are skipped:
  /// neighbouring beams are not independent, and cost scales with beams).
  size_t max_beams = 60;
  /// Each used beam's log-likelihood is multiplied by this (0..1]. Beams
  /// of one scan are not independent, and a product of 60 densities makes
  /// a belief far more certain than it is: a spread-out cloud collapses onto
  /// one wrong particle at the first scan. Tempering keeps the weights as
  /// flat as the real information warrants.
  double beam_exponent = 1.0;
  /// Beams at or beyond this range are skipped (no return, or too far to
  /// trust), m. The laser's own maximum is applied too.
  double laser_max_range = 30.0;
  /// Pose of the laser on the robot: m, m, rad.
  Pose2 laser_pose;
  /// The filter updates after the robot moved this far or turned this much
  /// since the last update: m, rad. In between, particles only follow the
  /// odometry (stationary scans would make the belief overconfident).
  double update_min_d = 0.1;
  double update_min_a = 0.2;
  /// Augmented MCL averaging rates per update (0 < slow << fast < 1);
  /// alpha_slow = 0 turns lost detection and recovery off.
  /// alpha_fast 0.3 notices a kidnapping within 2 or 3 updates (0.1, the
  /// classic value, took about 10 on the ACES log).
  double alpha_slow = 0.001;
  double alpha_fast = 0.3;
  /// The filter is lost while w_fast < lost_ratio * w_slow (0..1). On the
  /// ACES log w_fast stays above 0.8 w_slow while tracking and a belief put
  /// 4 m off settles at 0.35..0.6 of it.
  double lost_ratio = 0.6;
  /// Recovery: free-space poses drawn and scored against the measurement at
  /// each update while lost; the best recovery_keep of them are what is
  /// injected. 0 candidates: inject uniform free-space poses (classic
  /// augmented MCL), only while lost as well.
  size_t recovery_candidates = 20000;
  size_t recovery_keep = 500;
  /// Measurement updates between resamplings (1: every one).
  size_t resample_interval = 1;
};

/// One particle: a pose in the map frame (m, m, rad) and its weight.
struct Particle {
  Pose2 pose;
  double weight = 0;
};

/// A cluster of particles: one mode of the belief.
struct PoseHypothesis {
  Pose2 mean;           // m, m, rad
  Eigen::Matrix3d cov;  // (x, y, a): m^2, m*rad, rad^2
  double weight = 0;    // share of the belief, 0..1
};

/// A scan as the filter reads it: beams in the laser frame.
struct ScanView {
  double start_angle = 0;         // rad
  double angular_res = 0;         // rad
  double max_range = 0;           // no-return range, m
  std::span<const float> ranges;  // m
};

/// A measurement other than a scan (landmarks, fixes): how likely it is
/// from a pose.
class PoseLikelihood {
 public:
  virtual ~PoseLikelihood() = default;
  /// log p(measurement | pose); pose in the map frame: m, m, rad.
  virtual double log_likelihood(const Pose2& pose) const = 0;
  /// Independent observations it sums (0: nothing to weigh with). The
  /// recovery averages are kept per observation.
  virtual size_t terms() const = 0;
};

class ParticleFilter {
 public:
  /// The map must outlive the filter; the likelihood field is computed here.
  ParticleFilter(const OccupancyGrid& map, const MclParams& params);

  /// Global localization: max(global_particles, max_particles) poses
  /// uniform over the free cells.
  void init_global(Rng& rng);
  /// Pose tracking: max(min_particles, ...) poses from N(mean, cov); cov
  /// over (x, y, a): m^2, rad^2.
  void init_pose(const Pose2& mean, const Eigen::Matrix3d& cov, Rng& rng);

  /// Moves the particles by the odometry change since the previous call
  /// (the first call only records `odom`), then weighs and resamples them
  /// against `scan` when the robot moved enough. Returns true when a
  /// measurement update ran. `odom` and `scan` must be of the same instant.
  bool update(const Pose2& odom, const ScanView& scan, Rng& rng);
  /// The same with another kind of measurement of the same instant.
  bool update(const Pose2& odom, const PoseLikelihood& measurement, Rng& rng);
  /// Moves the particles by odometry only (no scan at this instant).
  void predict(const Pose2& odom, Rng& rng);
  /// Forgets the previous odometry pose: the next update() or predict()
  /// only records its pose. For an odometry source that restarted (a robot
  /// rebooted), whose new poses have no relation to the old ones.
  void reset_odometry() { has_odom_ = false; }

  /// Particle clusters, heaviest first (computed after each update).
  const std::vector<PoseHypothesis>& hypotheses() const { return hypotheses_; }
  /// The heaviest cluster's mean, m, m, rad.
  Pose2 best() const { return hypotheses_.empty() ? Pose2{} : hypotheses_.front().mean; }
  std::span<const Particle> particles() const { return particles_; }
  const OccupancyGrid& map() const { return *map_; }
  const LikelihoodField& field() const { return field_; }
  const MclParams& params() const { return params_; }

  /// Short- and long-term average per-beam likelihood (1/m).
  double w_slow() const { return w_slow_; }
  double w_fast() const { return w_fast_; }
  /// The filter's own verdict after the last measurement update: the scans
  /// fit its belief much worse than they used to (w_fast < lost_ratio *
  /// w_slow), so it is recovering. A new initialisation clears it.
  bool lost() const { return lost_; }
  size_t updates() const { return updates_; }

  /// Log-likelihood of `scan` seen from each pose (exposed for tests and
  /// benchmarks): sum over the used beams of log p(endpoint).
  double log_likelihood(const Pose2& pose, const ScanView& scan) const;

 private:
  /// Moves the particles; true when the robot moved enough to weigh them.
  bool begin_update(const Pose2& odom, Rng& rng);
  /// After the weights were set: lost detection, clusters, recovery
  /// candidates (scored by `score`: pose -> log-likelihood of the
  /// measurement), resampling.
  template <typename Score>
  bool finish_update(double w_avg, const Score& score, Rng& rng);
  void select_beams(const ScanView& scan);
  /// Sum over the selected beams of the endpoints' log-likelihoods from
  /// `pose` (map frame), in the grid's cell arithmetic.
  double beams_log_likelihood(const Pose2& pose) const;
  double weigh(const ScanView& scan);
  /// Fills candidates_ with the best-scoring of recovery_candidates draws.
  template <typename Score>
  void draw_candidates(const Score& score, Rng& rng);
  void resample(Rng& rng);
  Pose2 random_free_pose(Rng& rng) const;
  void cluster();

  const OccupancyGrid* map_;
  std::unordered_set<uint64_t> bins_;
  MclParams params_;
  LikelihoodField field_;
  std::vector<uint32_t> free_cells_;  // row * width + col
  std::vector<Particle> particles_;
  std::vector<Particle> scratch_;
  std::vector<double> cumulative_;
  std::vector<PoseHypothesis> hypotheses_;
  // A used beam's endpoint in the robot frame, m.
  struct Beam {
    double x, y;
  };
  std::vector<Beam> beams_;
  bool has_odom_ = false;
  Pose2 last_odom_;
  Pose2 moved_since_update_;  // accumulated |d|, |a| since the last update
  bool force_update_ = true;
  double w_slow_ = 0, w_fast_ = 0;
  bool lost_ = false;
  // Recovery poses for the next resampling, best first, and their scores.
  std::vector<Pose2> candidates_;
  std::vector<std::pair<double, uint32_t>> scored_;
  std::vector<Pose2> drawn_;
  size_t updates_ = 0;
  size_t since_resample_ = 0;
};

/// The KLD-sampling bound: particles needed so that, with probability
/// 1 - delta, the K-L divergence to the true posterior is below `error`
/// when the samples fall into `bins` histogram bins (Fox 2003).
size_t kld_bound(size_t bins, double error, double z);

}  // namespace troupe::desktop
