#include "drivers/fusion/fusion.h"

#include <algorithm>
#include <cmath>

#include "runtime/log.h"
#include "runtime/node.h"
#include "wire/address.h"

namespace troupe::drivers::fusion {

using Outcome = desktop::PoseEkf::Outcome;

bool Fusion::setup(Node& node, const DriverSetup& setup, std::string& error) {
  name_ = setup.name;
  for (DeviceId d : setup.required) {
    auto iface = wire::Interface(node.address(d).iface());
    DeviceId* slot = iface == wire::Interface::Position2d ? &odom_in_
                     : iface == wire::Interface::Imu      ? &imu_in_
                     : iface == wire::Interface::Localize ? &localize_in_
                     : iface == wire::Interface::Fiducial ? &fiducial_in_
                                                          : nullptr;
    if (slot == nullptr || *slot != kNoDevice) {
      error = "uses " + wire::format_address(node.address(d)) +
              ": fusion uses one each of position2d (odometry), imu, localize, fiducial";
      return false;
    }
    *slot = d;
  }
  if (odom_in_ == kNoDevice) {
    error = "fusion needs odometry: a position2d in \"uses\"";
    return false;
  }
  if (setup.provides.size() != 1 ||
      node.address(setup.provides[0]).iface() != uint16_t(wire::Interface::Position2d)) {
    error = "fusion provides exactly one position2d";
    return false;
  }
  out_ = setup.provides[0];
  OptionsView<Options> opt(setup);
  desktop::EkfParams p;
  p.accel_psd = opt->accel_psd();
  p.turn_accel_psd = opt->turn_accel_psd();
  p.pose_psd_xy = opt->pose_psd_xy();
  p.pose_psd_a = opt->pose_psd_a();
  p.odom_speed_sigma = opt->odom_speed_sigma();
  p.odom_turn_sigma = opt->odom_turn_sigma();
  p.history_s = opt->history();
  p.gate = opt->gate();
  p.max_gated = opt->max_gated();
  if (!(p.accel_psd > 0) || !(p.turn_accel_psd > 0) || p.pose_psd_xy < 0 || p.pose_psd_a < 0 ||
      !(p.odom_speed_sigma > 0) || !(p.odom_turn_sigma > 0) || !(opt->gyro_sigma() > 0)) {
    error = "noise options must be > 0 (pose_psd_xy and pose_psd_a >= 0)";
    return false;
  }
  if (!(p.history_s >= 0 && p.history_s <= 60) || p.gate < 0 || p.max_gated < 1) {
    error = "need history in [0, 60] s, gate >= 0, max_gated >= 1";
    return false;
  }
  if (!(opt->fix_min_var_xy() >= 0) || !(opt->fix_min_var_a() >= 0) || !(opt->fiducial_sigma_xy() > 0) ||
      !(opt->fiducial_sigma_a() > 0)) {
    error = "fix_min_var_* must be >= 0 and fiducial_sigma_* > 0";
    return false;
  }
  gyro_sigma_ = opt->gyro_sigma();
  fix_min_var_xy_ = opt->fix_min_var_xy();
  fix_min_var_a_ = opt->fix_min_var_a();
  fid_sigma_xy_ = opt->fiducial_sigma_xy();
  fid_sigma_a_ = opt->fiducial_sigma_a();
  if (opt->landmarks()) {
    for (const Landmark* l : *opt->landmarks()) {
      if (!landmarks_.emplace(l->id(), desktop::Pose2{l->x(), l->y(), l->a()}).second) {
        error = "landmark id " + std::to_string(l->id()) + " is listed twice";
        return false;
      }
    }
  }
  if (fiducial_in_ != kNoDevice && landmarks_.empty()) {
    error = "fusion uses a fiducial device but \"landmarks\" lists none";
    return false;
  }
  ekf_ = std::make_unique<desktop::PoseEkf>(p);
  if (opt->initial_var_xy() > 0) {
    Eigen::Matrix3d cov =
        Eigen::Vector3d(opt->initial_var_xy(), opt->initial_var_xy(), std::max(opt->initial_var_a(), 1e-6f))
            .asDiagonal();
    ekf_->reset(node.now_us() * 1e-6, {opt->initial_x(), opt->initial_y(), opt->initial_a()}, cov);
  }
  for (DeviceId d : {odom_in_, imu_in_, localize_in_, fiducial_in_}) {
    if (d != kNoDevice) node.subscribe(d, this);
  }
  return true;
}

void Fusion::on_outcome(Outcome o, const char* what) {
  if (o == Outcome::Invalid || o == Outcome::TooOld) {
    // Say it a few times, then only count: a broken source must not flood the log.
    if (++warned_ <= 10) {
      log_warn("%s: %s %s", name_.c_str(), what,
               o == Outcome::Invalid ? "is not finite or has a bad covariance: ignored"
                                     : "is older than the filter's history: dropped");
    }
  }
}

// An odometry clock this far behind the filter's means the source restarted, s.
constexpr double kRestartS = 1.0;

void Fusion::on_data(DeviceId source, const wire::Message& data) {
  double t = double(wire::time_us(*data.header())) * 1e-6;
  if (source == odom_in_) {
    const wire::Position2dState* s = data.body_as_Position2dState();
    if (s == nullptr || s->pose() == nullptr) return;
    if (ekf_->ready() && t + kRestartS < ekf_->time_s()) {
      // The robot restarted (its clock went back, e.g. a simulator run
      // again): the belief carries over to its new clock, or every input
      // would be "older than the history" until the clock caught up.
      const desktop::PoseEkf::State x = ekf_->state();
      const Eigen::Matrix3d cov = ekf_->covariance().topLeftCorner<3, 3>();
      double back_s = ekf_->time_s() - t;
      ekf_->reset(t, {x(0), x(1), x(2)}, cov);
      log_info("%s: odometry clock went back %.1f s (source restarted); continuing from the current belief",
               name_.c_str(), back_s);
    }
    Outcome o = ekf_->add_odometry(t, {s->pose()->x(), s->pose()->y(), s->pose()->a()});
    on_outcome(o, "odometry");
    if (o == Outcome::Applied || o == Outcome::AppliedLate) publish(t);
  } else if (source == imu_in_) {
    const wire::ImuState* s = data.body_as_ImuState();
    if (s == nullptr || s->gyro() == nullptr) return;
    on_outcome(ekf_->add_yaw_rate(t, s->gyro()->z(), gyro_sigma_), "yaw rate");
  } else if (source == localize_in_) {
    const wire::LocalizeState* s = data.body_as_LocalizeState();
    if (s == nullptr || s->hypotheses() == nullptr || s->hypotheses()->size() == 0) return;
    if (s->lost() != localizer_lost_) {
      localizer_lost_ = s->lost();
      log_info(localizer_lost_ ? "%s: the localizer says it is lost: its fixes are ignored until it is not"
                               : "%s: the localizer has found itself: its fixes are used again",
               name_.c_str());
    }
    // A lost localizer's best guess is a guess: applied, it would pull the
    // belief, or after max_gated refusals reset it, to wherever the
    // searching particles happen to cluster. The fix after it recovers
    // passes the gate, or resets the filter if it moved meanwhile.
    if (localizer_lost_) return;
    const wire::Hypothesis* h = s->hypotheses()->Get(0);
    const wire::Cov2d& c = h->cov();
    Eigen::Matrix3d cov;
    cov << c.xx(), c.xy(), c.xa(), c.xy(), c.yy(), c.ya(), c.xa(), c.ya(), c.aa();
    cov(0, 0) = std::max(cov(0, 0), fix_min_var_xy_);
    cov(1, 1) = std::max(cov(1, 1), fix_min_var_xy_);
    cov(2, 2) = std::max(cov(2, 2), fix_min_var_a_);
    Outcome o = ekf_->add_pose_fix(t, {h->mean().x(), h->mean().y(), h->mean().a()}, cov);
    on_outcome(o, "localize fix");
    if (o == Outcome::Applied || o == Outcome::AppliedLate) publish(t);
  } else if (source == fiducial_in_) {
    const wire::FiducialList* s = data.body_as_FiducialList();
    if (s == nullptr || s->fiducials() == nullptr) return;
    Eigen::Matrix3d cov = Eigen::Vector3d(fid_sigma_xy_ * fid_sigma_xy_, fid_sigma_xy_ * fid_sigma_xy_,
                                          fid_sigma_a_ * fid_sigma_a_)
                              .asDiagonal();
    bool applied = false;
    for (const wire::Fiducial* f : *s->fiducials()) {
      auto it = landmarks_.find(f->id());
      if (it == landmarks_.end()) continue;  // unidentified or not in the map
      Outcome o = ekf_->add_landmark(t, it->second, {f->x(), f->y(), f->yaw()}, cov);
      on_outcome(o, "fiducial sighting");
      applied |= o == Outcome::Applied || o == Outcome::AppliedLate;
    }
    if (applied) publish(t);
  }
}

void Fusion::publish(double time_s) {
  if (!ekf_->ready()) return;
  // The newest state, carried forward to the input's time when that is
  // newer (the first odometry sample after a fix adds no measurement).
  time_s = std::max(time_s, ekf_->time_s());
  desktop::PoseEkf::State x;
  desktop::PoseEkf::Cov p;
  ekf_->predict_to(time_s, x, p);
  auto& b = node_->begin();
  wire::Pose2d pose(float(x(0)), float(x(1)), float(x(2)));
  wire::Pose2d vel(float(x(3)), 0, float(x(4)));
  wire::Cov2d cov(float(p(0, 0)), float(p(0, 1)), float(p(0, 2)), float(p(1, 1)), float(p(1, 2)),
                  float(p(2, 2)));
  auto body = wire::CreatePosition2dState(b, &pose, &vel, false, &cov);
  node_->publish(out_, uint8_t(wire::Position2dDataSub::State), wire::Body::Position2dState, body.Union(),
                 uint64_t(std::llround(time_s * 1e6)));
}

extern const DriverEntry kEntry;
const DriverEntry kEntry{"fusion", []() -> Driver* { return new Fusion; }};

}  // namespace troupe::drivers::fusion
