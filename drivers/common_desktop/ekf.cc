#include "drivers/common_desktop/ekf.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace troupe::desktop {
namespace {

using Rows = Eigen::Matrix<double, Eigen::Dynamic, 5, 0, 3, 5>;
using Vec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1>;
using Sq = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;

bool finite(const Pose2& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.a);
}

// Symmetric and positive definite (a covariance a filter can divide by).
bool positive(const Eigen::Matrix3d& c) {
  if (!c.allFinite() || !c.isApprox(c.transpose(), 1e-9)) return false;
  return Eigen::LLT<Eigen::Matrix3d>(c).info() == Eigen::Success;
}

}  // namespace

void PoseEkf::reset(double t, const Pose2& pose, const Eigen::Matrix3d& cov) {
  Entry e;
  e.time_s = t;
  e.x << pose.x, pose.y, wrap_angle(pose.a), 0, 0;
  e.p.setZero();
  e.p.topLeftCorner<3, 3>() = cov;
  e.p(3, 3) = 1.0;  // (1 m/s)^2: the speeds are learnt from odometry
  e.p(4, 4) = 1.0;
  history_.clear();
  history_.push_back(e);
  gated_in_row_ = 0;
}

void PoseEkf::predict(double dt, State& x, Cov& p) const {
  if (dt <= 0) return;
  double c = std::cos(x(2)), s = std::sin(x(2)), v = x(3), w = x(4);
  Cov f = Cov::Identity();
  f(0, 2) = -v * s * dt;
  f(0, 3) = c * dt;
  f(1, 2) = v * c * dt;
  f(1, 3) = s * dt;
  f(2, 4) = dt;
  x(0) += v * c * dt;
  x(1) += v * s * dt;
  x(2) = wrap_angle(x(2) + w * dt);
  Eigen::Matrix<double, 5, 1> q;
  q << params_.pose_psd_xy, params_.pose_psd_xy, params_.pose_psd_a, params_.accel_psd,
      params_.turn_accel_psd;
  p = f * p * f.transpose();
  p.diagonal() += q * dt;
}

void PoseEkf::predict_to(double t, State& x, Cov& p) const {
  x = state();
  p = covariance();
  predict(t - time_s(), x, p);
}

bool PoseEkf::correct(const Measurement& m, State& x, Cov& p, bool gate) {
  Rows h;
  Vec y;
  Sq r;
  switch (m.kind) {
    case Kind::Start:
      return true;
    case Kind::Speeds:
      h.setZero(2, 5);
      h(0, 3) = h(1, 4) = 1;
      y.resize(2);
      y << m.z(0) - x(3), m.z(1) - x(4);
      r = m.r.topLeftCorner<2, 2>();
      break;
    case Kind::YawRate:
      h.setZero(1, 5);
      h(0, 4) = 1;
      y.resize(1);
      y << m.z(0) - x(4);
      r = m.r.topLeftCorner<1, 1>();
      break;
    case Kind::Pose:
      h.setZero(3, 5);
      h(0, 0) = h(1, 1) = h(2, 2) = 1;
      y.resize(3);
      y << m.z(0) - x(0), m.z(1) - x(1), wrap_angle(m.z(2) - x(2));
      r = m.r;
      break;
    case Kind::Landmark: {
      // Expected sighting: the landmark in the robot frame.
      double c = std::cos(x(2)), s = std::sin(x(2));
      double dx = m.landmark.x - x(0), dy = m.landmark.y - x(1);
      double zx = c * dx + s * dy, zy = -s * dx + c * dy;
      h.setZero(3, 5);
      h.row(0) << -c, -s, zy, 0, 0;
      h.row(1) << s, -c, -zx, 0, 0;
      h.row(2) << 0, 0, -1, 0, 0;
      y.resize(3);
      y << m.z(0) - zx, m.z(1) - zy, wrap_angle(m.z(2) - wrap_angle(m.landmark.a - x(2)));
      r = m.r;
      break;
    }
  }
  Sq s = h * p * h.transpose() + r;
  Sq s_inv = s.inverse();
  if (gate && params_.gate > 0 && (m.kind == Kind::Pose || m.kind == Kind::Landmark)) {
    double d2 = y.dot(s_inv * y);
    if (!(d2 <= params_.gate)) return false;
  }
  Eigen::Matrix<double, 5, Eigen::Dynamic, 0, 5, 3> k = p * h.transpose() * s_inv;
  x += k * y;
  x(2) = wrap_angle(x(2));
  // Joseph form: stays symmetric and positive under rounding.
  Cov ikh = Cov::Identity() - k * h;
  p = ikh * p * ikh.transpose() + k * r * k.transpose();
  return true;
}

PoseEkf::Outcome PoseEkf::add(double t, const Measurement& m) {
  if (!std::isfinite(t) || !m.z.allFinite() || !m.r.allFinite()) return Outcome::Invalid;
  if (history_.empty()) return Outcome::NotReady;
  if (t < history_.front().time_s) {
    ++dropped_;
    return Outcome::TooOld;
  }
  auto at = std::upper_bound(history_.begin(), history_.end(), t,
                             [](double time, const Entry& e) { return time < e.time_s; });
  size_t idx = size_t(at - history_.begin());
  bool late = idx < history_.size();
  Entry e;
  e.time_s = t;
  e.m = m;
  e.x = history_[idx - 1].x;
  e.p = history_[idx - 1].p;
  predict(t - history_[idx - 1].time_s, e.x, e.p);
  e.accepted = correct(m, e.x, e.p, true);
  Outcome outcome = late ? Outcome::AppliedLate : Outcome::Applied;
  if (!e.accepted) {
    ++gated_total_;
    if (++gated_in_row_ < params_.max_gated || m.kind != Kind::Pose) return Outcome::Gated;
    // The fixes keep disagreeing: believe them, the filter is the lost one.
    e.x.head<3>() = m.z;
    e.p.topRows<3>().setZero();
    e.p.leftCols<3>().setZero();
    e.p.topLeftCorner<3, 3>() = m.r;
    e.accepted = true;
  }
  if (m.kind == Kind::Pose || m.kind == Kind::Landmark) gated_in_row_ = 0;
  if (late) ++late_;
  history_.insert(history_.begin() + long(idx), e);
  // Filter the later measurements again from the corrected past.
  for (size_t j = idx + 1; j < history_.size(); ++j) {
    Entry& n = history_[j];
    n.x = history_[j - 1].x;
    n.p = history_[j - 1].p;
    predict(n.time_s - history_[j - 1].time_s, n.x, n.p);
    if (n.accepted) correct(n.m, n.x, n.p, false);
  }
  prune();
  return outcome;
}

void PoseEkf::prune() {
  double horizon = history_.back().time_s - params_.history_s;
  while (history_.size() > 1 && history_[1].time_s <= horizon) history_.pop_front();
}

PoseEkf::Outcome PoseEkf::add_odometry(double t, const Pose2& odom) {
  if (!std::isfinite(t) || !finite(odom)) return Outcome::Invalid;
  if (!has_odom_ || t <= odom_time_s_) {
    // The first reading, or one not after the last (a restarted source):
    // start a new interval from it.
    has_odom_ = true;
    odom_time_s_ = t;
    last_odom_ = odom;
    return ready() ? Outcome::Applied : Outcome::NotReady;
  }
  double dt = t - odom_time_s_;
  Pose2 d = relative(last_odom_, odom);
  odom_time_s_ = t;
  last_odom_ = odom;
  Measurement m;
  m.kind = Kind::Speeds;
  // Signed distance along the chord: a reversing base has d.x < 0.
  m.z << std::copysign(std::hypot(d.x, d.y), d.x) / dt, d.a / dt, 0;
  double sv = params_.odom_speed_sigma, sw = params_.odom_turn_sigma;
  m.r.diagonal() << sv * sv, sw * sw, 1;
  return add(t, m);
}

PoseEkf::Outcome PoseEkf::add_yaw_rate(double t, double rate, double sigma) {
  if (!(sigma > 0) || !std::isfinite(sigma)) return Outcome::Invalid;
  Measurement m;
  m.kind = Kind::YawRate;
  m.z << rate, 0, 0;
  m.r.diagonal() << sigma * sigma, 1, 1;
  return add(t, m);
}

PoseEkf::Outcome PoseEkf::add_pose_fix(double t, const Pose2& pose, const Eigen::Matrix3d& cov) {
  if (!std::isfinite(t) || !finite(pose) || !positive(cov)) return Outcome::Invalid;
  if (!ready()) {
    reset(t, pose, cov);
    return Outcome::Applied;
  }
  Measurement m;
  m.kind = Kind::Pose;
  m.z << pose.x, pose.y, wrap_angle(pose.a);
  m.r = cov;
  return add(t, m);
}

PoseEkf::Outcome PoseEkf::add_landmark(double t, const Pose2& landmark, const Pose2& seen,
                                       const Eigen::Matrix3d& cov) {
  if (!std::isfinite(t) || !finite(landmark) || !finite(seen) || !positive(cov)) return Outcome::Invalid;
  Measurement m;
  m.kind = Kind::Landmark;
  m.z << seen.x, seen.y, wrap_angle(seen.a);
  m.r = cov;
  m.landmark = landmark;
  return add(t, m);
}

}  // namespace troupe::desktop
