#include "drivers/common_desktop/particle_filter.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "drivers/common_desktop/pose_bins.h"

namespace troupe::desktop {
namespace {

// The j-th point of the base-2 van der Corput sequence in [0, 1): every
// prefix of length 2^k is the evenly spaced comb {i / 2^k}.
double van_der_corput(uint32_t j) {
  j = (j << 16) | (j >> 16);
  j = ((j & 0x00ff00ffu) << 8) | ((j & 0xff00ff00u) >> 8);
  j = ((j & 0x0f0f0f0fu) << 4) | ((j & 0xf0f0f0f0u) >> 4);
  j = ((j & 0x33333333u) << 2) | ((j & 0xccccccccu) >> 2);
  j = ((j & 0x55555555u) << 1) | ((j & 0xaaaaaaaau) >> 1);
  return double(j) * (1.0 / 4294967296.0);
}

}  // namespace

size_t kld_bound(size_t bins, double error, double z) {
  if (bins <= 1) return 1;
  double k = double(bins - 1);
  double a = 2.0 / (9.0 * k);
  double b = 1.0 - a + std::sqrt(a) * z;
  return size_t(std::ceil(k / (2.0 * error) * b * b * b));
}

ParticleFilter::ParticleFilter(const OccupancyGrid& map, const MclParams& params)
    : map_(&map), params_(params), field_(map, params.sensor) {
  for (uint32_t r = 0; r < map.height(); ++r) {
    for (uint32_t c = 0; c < map.width(); ++c) {
      if (map.at(c, r) == CellState::Free) free_cells_.push_back(r * map.width() + c);
    }
  }
  params_.min_particles = std::max<size_t>(1, std::min(params_.min_particles, params_.max_particles));
}

Pose2 ParticleFilter::random_free_pose(Rng& rng) const {
  Pose2 p;
  p.a = (uniform01(rng) * 2 - 1) * kPi;
  if (free_cells_.empty()) {  // a map without free cells: anywhere on it
    map_->cell_center(int64_t(uniform01(rng) * map_->width()), int64_t(uniform01(rng) * map_->height()), p.x,
                      p.y);
    return p;
  }
  uint32_t cell = free_cells_[size_t(uniform01(rng) * double(free_cells_.size()))];
  map_->cell_center(cell % map_->width(), cell / map_->width(), p.x, p.y);
  // Anywhere inside the cell, not only its centre.
  p.x += (uniform01(rng) - 0.5) * map_->resolution();
  p.y += (uniform01(rng) - 0.5) * map_->resolution();
  return p;
}

void ParticleFilter::init_global(Rng& rng) {
  particles_.resize(std::max(params_.global_particles, params_.max_particles));
  double w = 1.0 / double(particles_.size());
  for (Particle& p : particles_) p = {random_free_pose(rng), w};
  w_slow_ = w_fast_ = 0;
  lost_ = false;
  force_update_ = true;
  since_resample_ = 0;
  cluster();
}

void ParticleFilter::init_pose(const Pose2& mean, const Eigen::Matrix3d& cov, Rng& rng) {
  // cov = V diag(l) V^T: draw in the eigenbasis; a singular direction just
  // gets no spread.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(0.5 * (cov + cov.transpose()));
  Eigen::Matrix3d scale = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
  particles_.resize(params_.max_particles);
  double w = 1.0 / double(particles_.size());
  for (Particle& p : particles_) {
    Eigen::Vector3d n(gaussian(rng, 1), gaussian(rng, 1), gaussian(rng, 1));
    Eigen::Vector3d d = scale * n;
    p = {{mean.x + d.x(), mean.y + d.y(), wrap_angle(mean.a + d.z())}, w};
  }
  w_slow_ = w_fast_ = 0;
  lost_ = false;
  force_update_ = true;
  since_resample_ = 0;
  cluster();
}

void ParticleFilter::predict(const Pose2& odom, Rng& rng) {
  if (!std::isfinite(odom.x) || !std::isfinite(odom.y) || !std::isfinite(odom.a)) return;
  if (!has_odom_) {
    has_odom_ = true;
    last_odom_ = odom;
    return;
  }
  OdometryMotion m = decompose(last_odom_, odom);
  moved_since_update_.x += m.trans;
  moved_since_update_.a += std::fabs(wrap_angle(odom.a - last_odom_.a));
  last_odom_ = odom;
  if (m.trans == 0 && m.rot1 == 0 && m.rot2 == 0) return;
  for (Particle& p : particles_) p.pose = sample_motion(p.pose, m, params_.motion, rng);
}

void ParticleFilter::select_beams(const ScanView& scan) {
  beams_.clear();
  size_t n = scan.ranges.size();
  size_t want = std::max<size_t>(1, params_.max_beams);
  double step = n > want ? double(n) / double(want) : 1.0;
  // Ranges beyond 1000 km are nonsense from any laser (and would overflow
  // the cell arithmetic); non-finite geometry makes every beam unusable.
  double limit = std::min({scan.max_range, params_.laser_max_range, 1e6});
  const Pose2& lp = params_.laser_pose;
  if (!std::isfinite(scan.start_angle) || !std::isfinite(scan.angular_res)) return;
  for (double f = 0; size_t(f) < n; f += step) {
    size_t i = size_t(f);
    double r = scan.ranges[i];
    if (!std::isfinite(r) || r <= 0.01 || r >= limit) continue;
    double b = lp.a + scan.start_angle + double(i) * scan.angular_res;
    beams_.push_back({lp.x + r * std::cos(b), lp.y + r * std::sin(b)});
  }
}

double ParticleFilter::log_likelihood(const Pose2& pose, const ScanView& scan) const {
  const_cast<ParticleFilter*>(this)->select_beams(scan);
  double c = std::cos(pose.a), s = std::sin(pose.a), lw = 0;
  for (const Beam& b : beams_)
    lw += field_.log_likelihood(pose.x + c * b.x - s * b.y, pose.y + s * b.x + c * b.y);
  return lw;
}

double ParticleFilter::beams_log_likelihood(const Pose2& pose) const {
  // The hot loop: the pose is taken into the grid's frame in cell units
  // once, so a beam costs two multiply-adds, a floor and a load.
  const double inv_res = 1.0 / map_->resolution();
  Pose2 q = relative(map_->origin(), pose);
  double qx = q.x * inv_res, qy = q.y * inv_res;
  if (!(std::fabs(qx) < 1e12 && std::fabs(qy) < 1e12)) {  // far off the map: no lookups to overflow
    return double(field_.log_likelihood_far()) * double(beams_.size());
  }
  // floor() without the libm call (x86-64 has no inline floor before SSE4.1).
  auto cell = [](double g) {
    int64_t i = int64_t(g);
    return i - int64_t(g < double(i));
  };
  double c = std::cos(q.a) * inv_res, s = std::sin(q.a) * inv_res, lw = 0;
  for (const Beam& b : beams_) {
    lw += field_.cell_log_likelihood(cell(qx + c * b.x - s * b.y), cell(qy + s * b.x + c * b.y));
  }
  return lw;
}

double ParticleFilter::weigh(const ScanView& scan) {
  select_beams(scan);
  if (beams_.empty()) return 0;
  // log(w_prev * L), then normalise with the maximum subtracted: the raw
  // product of 60 densities under- or overflows a double.
  double top = -std::numeric_limits<double>::infinity();
  for (Particle& p : particles_) {
    p.weight = params_.beam_exponent * beams_log_likelihood(p.pose) + std::log(std::max(p.weight, 1e-300));
    top = std::max(top, p.weight);
  }
  double sum = 0;
  for (Particle& p : particles_) sum += (p.weight = std::exp(p.weight - top));
  for (Particle& p : particles_) p.weight /= sum;
  // The marginal likelihood sum(w_prev * L), per beam so that it does not
  // depend on how many beams this scan had.
  return std::exp((top + std::log(sum)) / (params_.beam_exponent * double(beams_.size())));
}

bool ParticleFilter::begin_update(const Pose2& odom, Rng& rng) {
  // Without a trustworthy odometry pose the measurement cannot be placed.
  if (!std::isfinite(odom.x) || !std::isfinite(odom.y) || !std::isfinite(odom.a)) return false;
  predict(odom, rng);
  if (particles_.empty()) return false;
  bool moved = moved_since_update_.x >= params_.update_min_d || moved_since_update_.a >= params_.update_min_a;
  if (!moved && !force_update_) {
    cluster();  // the particles followed the odometry
    return false;
  }
  return true;
}

template <typename Score>
bool ParticleFilter::finish_update(double w_avg, const Score& score, Rng& rng) {
  force_update_ = false;
  moved_since_update_ = {};
  ++updates_;
  if (w_slow_ == 0) {
    w_slow_ = w_fast_ = w_avg;
  } else {
    w_fast_ += params_.alpha_fast * (w_avg - w_fast_);
    // While lost the long-term average holds still: learning the lost
    // level would make a filter that stays lost stop noticing it.
    if (!lost_) w_slow_ += params_.alpha_slow * (w_avg - w_slow_);
  }
  lost_ = params_.alpha_slow > 0 && w_slow_ > 0 && w_fast_ < params_.lost_ratio * w_slow_;
  // Clusters from the weighted set: resampling only adds noise to the mean.
  cluster();
  candidates_.clear();
  if (++since_resample_ >= std::max<size_t>(1, params_.resample_interval) || lost_) {
    since_resample_ = 0;
    if (lost_) draw_candidates(score, rng);
    resample(rng);
  }
  return true;
}

// Not inlined: the cold path of a lost filter stays out of the update's hot
// code (and shows up by name in a profile).
template <typename Score>
[[gnu::noinline]] void ParticleFilter::draw_candidates(const Score& score, Rng& rng) {
  const size_t n = params_.recovery_candidates;
  if (n == 0) return;  // resample() draws uniform poses itself
  drawn_.resize(n);
  scored_.resize(n);
  for (size_t i = 0; i < n; ++i) {
    drawn_[i] = random_free_pose(rng);
    scored_[i] = {score(drawn_[i]), uint32_t(i)};
  }
  const size_t keep = std::clamp<size_t>(params_.recovery_keep, 1, n);
  // Best first; ties (equal scores) broken by draw order for determinism.
  std::partial_sort(scored_.begin(), scored_.begin() + long(keep), scored_.end(),
                    [](const auto& a, const auto& b) {
                      return a.first > b.first || (a.first == b.first && a.second < b.second);
                    });
  for (size_t i = 0; i < keep; ++i) candidates_.push_back(drawn_[scored_[i].second]);
}

bool ParticleFilter::update(const Pose2& odom, const ScanView& scan, Rng& rng) {
  if (!begin_update(odom, rng)) return false;
  double w_avg = weigh(scan);
  if (beams_.empty()) {  // nothing to measure with: keep the belief
    cluster();
    return false;
  }
  return finish_update(
      w_avg, [this](const Pose2& p) { return beams_log_likelihood(p); }, rng);
}

bool ParticleFilter::update(const Pose2& odom, const PoseLikelihood& measurement, Rng& rng) {
  if (!begin_update(odom, rng)) return false;
  const size_t terms = measurement.terms();
  if (terms == 0) {  // nothing observed: keep the belief
    cluster();
    return false;
  }
  // As weigh(): in log space, normalised with the maximum subtracted.
  double top = -std::numeric_limits<double>::infinity();
  for (Particle& p : particles_) {
    p.weight = measurement.log_likelihood(p.pose) + std::log(std::max(p.weight, 1e-300));
    top = std::max(top, p.weight);
  }
  double sum = 0;
  for (Particle& p : particles_) sum += (p.weight = std::exp(p.weight - top));
  for (Particle& p : particles_) p.weight /= sum;
  return finish_update(
      std::exp((top + std::log(sum)) / double(terms)),
      [&measurement](const Pose2& p) { return measurement.log_likelihood(p); }, rng);
}

void ParticleFilter::resample(Rng& rng) {
  cumulative_.resize(particles_.size());
  double acc = 0;
  for (size_t i = 0; i < particles_.size(); ++i) cumulative_[i] = (acc += particles_[i].weight);
  // Injected only while lost: tracking keeps every particle for the belief.
  double p_random = lost_ ? std::max(0.0, 1.0 - w_fast_ / w_slow_) : 0.0;
  double offset = uniform01(rng);
  PoseBins bins(params_.bin_xy, params_.bin_a);
  bins_.clear();
  scratch_.clear();
  size_t randoms = 0;
  uint32_t j = 0;
  while (scratch_.size() < params_.max_particles) {
    Pose2 pose;
    if (p_random > 0 && uniform01(rng) < p_random) {
      pose = candidates_.empty() ? random_free_pose(rng) : candidates_[randoms % candidates_.size()];
      ++randoms;
    } else {
      double u = van_der_corput(j++) + offset;
      u = (u >= 1.0 ? u - 1.0 : u) * acc;
      size_t i = size_t(std::upper_bound(cumulative_.begin(), cumulative_.end(), u) - cumulative_.begin());
      pose = particles_[std::min(i, particles_.size() - 1)].pose;
    }
    scratch_.push_back({pose, 1.0});
    bins_.insert(bins.key(pose));
    if (scratch_.size() >= params_.min_particles &&
        scratch_.size() >= kld_bound(bins_.size(), params_.kld_error, params_.kld_z)) {
      break;
    }
  }
  double w = 1.0 / double(scratch_.size());
  for (Particle& p : scratch_) p.weight = w;
  particles_.swap(scratch_);
}

}  // namespace troupe::desktop
