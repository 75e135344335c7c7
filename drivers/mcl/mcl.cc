#include "drivers/mcl/mcl.h"

#include <algorithm>
#include <cmath>

#include "runtime/log.h"
#include "runtime/node.h"
#include "wire/address.h"

namespace troupe::drivers::mcl {
namespace {

constexpr uint64_t kRetryUs = 1'000'000;  // map fetch retry

wire::Cov2d to_wire(const Eigen::Matrix3d& c) {
  return wire::Cov2d(float(c(0, 0)), float(c(0, 1)), float(c(0, 2)), float(c(1, 1)), float(c(1, 2)),
                     float(c(2, 2)));
}

// A restarted odometry source starts again from its origin; no wheel
// reports a pose within this of it while driving through (m, rad).
constexpr double kOriginM = 1e-3, kOriginRad = 1e-3;
// Odometry never moves by less than this between samples, however close in
// time they are (timestamp jitter), m and rad.
constexpr double kJitterM = 0.05, kJitterRad = 0.05;
// A silence counts as at most this much driving time: the speed bounds
// alone would pass any jump after a long enough gap, s.
constexpr double kMaxCreditedGapS = 1.0;

// Why `to`, `dt_s` after `from`, cannot be motion of the same odometry
// (nullptr: it can): the robot's node restarted while the clock ran on.
// Speed bounds <= 0 are not checked.
const char* odometry_break(const desktop::Pose2& from, const desktop::Pose2& to, double dt_s,
                           double max_speed, double max_turn_rate) {
  const double dt = std::min(dt_s, kMaxCreditedGapS);
  const double moved = desktop::distance(from, to), turned = std::fabs(desktop::wrap_angle(to.a - from.a));
  const bool at_origin = std::hypot(to.x, to.y) < kOriginM && std::fabs(to.a) < kOriginRad;
  if (at_origin && (moved >= kJitterM || turned >= kJitterRad)) return "jumped back to its origin";
  if (max_speed > 0 && moved > max_speed * dt + kJitterM) return "moved faster than odom_max_speed";
  if (max_turn_rate > 0 && turned > max_turn_rate * dt + kJitterRad)
    return "turned faster than odom_max_turn_rate";
  return nullptr;
}

Eigen::Matrix3d from_wire(const wire::Cov2d& c) {
  Eigen::Matrix3d m;
  m << c.xx(), c.xy(), c.xa(), c.xy(), c.yy(), c.ya(), c.xa(), c.ya(), c.aa();
  return m;
}

}  // namespace

bool Mcl::setup(Node& node, const DriverSetup& setup, std::string& error) {
  name_ = setup.name;
  for (DeviceId d : setup.required) {
    auto iface = wire::Interface(node.address(d).iface());
    DeviceId* slot = iface == wire::Interface::Position2d ? &odom_in_
                     : iface == wire::Interface::Ranger   ? &scan_in_
                     : iface == wire::Interface::Map      ? &map_in_
                     : iface == wire::Interface::Fiducial ? &landmarks_in_
                                                          : nullptr;
    if (slot == nullptr || *slot != kNoDevice) {
      error = "uses " + wire::format_address(node.address(d)) +
              ": mcl uses one position2d (odometry), one ranger (laser) or fiducial (landmarks), and one map";
      return false;
    }
    *slot = d;
  }
  if (odom_in_ == kNoDevice || (scan_in_ == kNoDevice && landmarks_in_ == kNoDevice) ||
      (map_in_ == kNoDevice && landmarks_in_ == kNoDevice)) {
    error =
        "mcl needs \"uses\": a position2d (odometry), a ranger (laser) and a map; or a position2d and a "
        "fiducial (landmarks, with landmark_table)";
    return false;
  }
  for (DeviceId d : setup.provides) {
    auto iface = wire::Interface(node.address(d).iface());
    if (iface == wire::Interface::Localize && localize_ == kNoDevice) {
      localize_ = d;
    } else if (iface == wire::Interface::Position2d && position_ == kNoDevice) {
      position_ = d;
    } else {
      error =
          "provides " + wire::format_address(node.address(d)) + ": mcl provides a localize and a position2d";
      return false;
    }
  }
  if (localize_ == kNoDevice) {
    error = "mcl provides a localize device (and optionally a position2d)";
    return false;
  }

  OptionsView<Options> opt(setup);
  desktop::MclParams& p = params_;
  p.min_particles = opt->min_particles();
  p.max_particles = opt->max_particles();
  p.kld_error = opt->kld_error();
  p.kld_z = opt->kld_z();
  p.bin_xy = opt->bin_xy();
  p.bin_a = opt->bin_a();
  p.motion = {opt->rot_rot(), opt->rot_trans(), opt->trans_trans(), opt->trans_rot()};
  p.sensor.sigma_hit = opt->sigma_hit();
  p.sensor.surface = opt->surface_field();
  p.sensor.z_hit = opt->z_hit();
  p.sensor.z_rand = opt->z_rand();
  p.sensor.max_distance = opt->max_distance();
  p.sensor.max_range = opt->laser_max_range();
  p.max_beams = opt->max_beams();
  p.laser_max_range = opt->laser_max_range();
  p.laser_pose = {opt->laser_x(), opt->laser_y(), opt->laser_a()};
  p.update_min_d = opt->update_min_d();
  p.update_min_a = opt->update_min_a();
  p.alpha_slow = opt->alpha_slow();
  p.alpha_fast = opt->alpha_fast();
  p.resample_interval = opt->resample_interval();
  p.global_particles = opt->global_particles();
  p.beam_exponent = opt->beam_exponent();
  p.lost_ratio = opt->lost_ratio();
  p.recovery_candidates = opt->recovery_candidates();
  p.recovery_keep = opt->recovery_keep();
  odom_max_speed_ = opt->odom_max_speed();
  odom_max_turn_rate_ = opt->odom_max_turn_rate();
  if (p.min_particles == 0 || p.min_particles > p.max_particles || p.max_particles > 1'000'000) {
    error = "need 0 < min_particles <= max_particles <= 1000000";
    return false;
  }
  if (!(p.kld_error > 0) || !(p.kld_z > 0) || !(p.bin_xy > 0) || !(p.bin_a > 0)) {
    error = "kld_error, kld_z, bin_xy and bin_a must be > 0";
    return false;
  }
  if (!(p.sensor.sigma_hit > 0) || p.sensor.z_hit < 0 || p.sensor.z_rand < 0 ||
      !(p.sensor.z_hit + p.sensor.z_rand > 0) || !(p.sensor.max_distance > 0) || !(p.laser_max_range > 0)) {
    error = "sigma_hit, max_distance and laser_max_range must be > 0, z_hit and z_rand >= 0 and not both 0";
    return false;
  }
  if (p.motion.rot_rot < 0 || p.motion.rot_trans < 0 || p.motion.trans_trans < 0 || p.motion.trans_rot < 0) {
    error = "motion noise (rot_rot, rot_trans, trans_trans, trans_rot) must be >= 0";
    return false;
  }
  if (p.global_particles > 1'000'000 || !(p.beam_exponent > 0 && p.beam_exponent <= 1)) {
    error = "need global_particles <= 1000000 and beam_exponent in (0, 1]";
    return false;
  }
  if (p.max_beams == 0 || p.alpha_slow < 0 || p.alpha_fast < p.alpha_slow || p.alpha_fast > 1) {
    error = "need max_beams > 0 and 0 <= alpha_slow <= alpha_fast <= 1";
    return false;
  }
  if (!(p.lost_ratio > 0 && p.lost_ratio < 1) || p.recovery_candidates > 10'000'000 || p.recovery_keep == 0) {
    error = "need lost_ratio in (0, 1), recovery_candidates <= 10000000 and recovery_keep > 0";
    return false;
  }
  if (!(odom_max_speed_ >= 0) || !(odom_max_turn_rate_ >= 0)) {
    error = "odom_max_speed and odom_max_turn_rate must be >= 0 (0: not checked)";
    return false;
  }
  if (!(opt->odom_wait() >= 0 && opt->odom_wait() <= 10)) {
    error = "odom_wait must be in [0, 10] s";
    return false;
  }
  odom_wait_us_ = uint64_t(opt->odom_wait() * 1e6);
  rng_.seed(opt->seed());
  if (opt->initial_var_xy() > 0) {
    init_ = Init::Pose;
    init_pose_ = {opt->initial_x(), opt->initial_y(), opt->initial_a()};
    init_cov_ =
        Eigen::Vector3d(opt->initial_var_xy(), opt->initial_var_xy(), std::max(opt->initial_var_a(), 1e-6f))
            .asDiagonal();
  }
  if (!setup_landmarks(opt, error)) return false;
  odom_.resize(kOdomHistory);
  node.subscribe(odom_in_, this);
  if (scan_in_ != kNoDevice) node.subscribe(scan_in_, this);
  if (landmarks_in_ != kNoDevice) node.subscribe(landmarks_in_, this);
  if (map_in_ == kNoDevice) {
    // Landmarks without a map: the table's grid is where the robot can be.
    const double res = 0.1;
    const auto w = uint32_t(std::ceil((table_.max_x() - table_.min_x()) / res)) + 1;
    const auto h = uint32_t(std::ceil((table_.max_y() - table_.min_y()) / res)) + 1;
    start_filter(
        desktop::OccupancyGrid(w, h, res, {table_.min_x(), table_.min_y(), 0}, desktop::CellState::Free));
    return true;
  }
  // The map is fetched once every driver is set up: its provider may be
  // listed after this one.
  fetch_timer_ = node.loop().start_timer(0, 0, this);
  if (fetch_timer_ == 0) {
    error = "no timer left";
    return false;
  }
  return true;
}

bool Mcl::setup_landmarks(const OptionsView<Options>& opt, std::string& error) {
  const bool has_table = opt->landmark_table() && opt->landmark_table()->size() > 0;
  if (!has_table) {
    if (landmarks_in_ == kNoDevice) return true;
    error = "uses a fiducial device but landmark_table names no table";
    return false;
  }
  if (landmarks_in_ == kNoDevice) {
    error = "landmark_table needs a fiducial device (landmark detections) in \"uses\"";
    return false;
  }
  std::string why;
  if (!table_.load(opt->landmark_table()->str(), why)) {
    error = "landmark_table: " + why;
    return false;
  }
  desktop::LandmarkModelParams lp;
  lp.sigma_distance = opt->landmark_sigma_distance();
  lp.sigma_distance_per_m = opt->landmark_sigma_distance_per_m();
  lp.sigma_bearing = opt->landmark_sigma_bearing();
  if (!(lp.sigma_distance > 0) || !(lp.sigma_distance_per_m >= 0) || !(lp.sigma_bearing > 0)) {
    error =
        "landmark_sigma_distance and landmark_sigma_bearing must be > 0, landmark_sigma_distance_per_m >= 0";
    return false;
  }
  landmark_model_ = std::make_unique<desktop::LandmarkLikelihood>(table_, lp);
  seen_.reserve(64);
  return true;
}

void Mcl::on_timer(TimerId id) {
  if (id == fetch_timer_) {
    fetch_timer_ = 0;
    if (!fetch_.start(*node_, *this, map_in_)) {
      log_warn("%s: cannot ask %s for the map yet; retrying", name_.c_str(),
               wire::format_address(node_->address(map_in_)).c_str());
      fetch_timer_ = node_->loop().start_timer(kRetryUs, 0, this);
    }
  } else if (id == wait_timer_) {
    wait_timer_ = 0;
    process_pending_scan(true);
  }
}

void Mcl::on_reply(DeviceId device, const wire::Message& reply) {
  if (device != map_in_) return;
  std::string error;
  if (fetch_.on_reply(reply, error)) {
    start_filter(std::move(fetch_.grid()));
  } else if (!fetch_.busy() && !filter_ && !error.empty()) {
    log_warn("%s: %s; retrying in %.0f s", name_.c_str(), error.c_str(), kRetryUs * 1e-6);
    if (fetch_timer_ == 0) fetch_timer_ = node_->loop().start_timer(kRetryUs, 0, this);
  }
}

void Mcl::start_filter(desktop::OccupancyGrid map) {
  map_ = std::move(map);
  filter_ = std::make_unique<desktop::ParticleFilter>(map_, params_);
  log_info("%s: map %ux%u cells of %.3f m; %s", name_.c_str(), map_.width(), map_.height(), map_.resolution(),
           init_ == Init::Global ? "global localization" : "tracking from the initial pose");
  apply_init();
}

void Mcl::apply_init() {
  if (!filter_) return;
  if (init_ == Init::Global) {
    filter_->init_global(rng_);
  } else {
    filter_->init_pose(init_pose_, init_cov_, rng_);
  }
}

void Mcl::on_data(DeviceId source, const wire::Message& data) {
  if (source == odom_in_) {
    on_odometry(data);
  } else if (source == scan_in_) {
    on_scan(data);
  } else if (source == landmarks_in_) {
    on_landmarks(data);
  }
}

void Mcl::on_odometry(const wire::Message& data) {
  const wire::Position2dState* s = data.body_as_Position2dState();
  if (s == nullptr || s->pose() == nullptr) return;
  desktop::Pose2 pose{s->pose()->x(), s->pose()->y(), s->pose()->a()};
  if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.a)) return;
  uint64_t t = wire::time_us(*data.header());
  if (odom_count_ > 0) {
    const OdomSample& last = odom_[(odom_head_ + kOdomHistory - 1) % kOdomHistory];
    // The source restarted when its clock went back (a simulator), or when
    // its pose jumped while the clock ran on (a robot's node rebooted):
    // older samples no longer belong, and its poses start from a new origin.
    const char* why = t < last.time_us ? "its clock went back"
                                       : odometry_break(last.pose, pose, double(t - last.time_us) * 1e-6,
                                                        odom_max_speed_, odom_max_turn_rate_);
    if (why != nullptr) {
      odom_count_ = 0;
      if (filter_) {
        filter_->predict(last.pose, rng_);  // the motion up to the restart still counts
        filter_->reset_odometry();
      }
      log_info("%s: odometry restarted (%s); continuing from the current belief", name_.c_str(), why);
    }
  }
  odom_[odom_head_] = {t, pose};
  odom_head_ = (odom_head_ + 1) % kOdomHistory;
  odom_count_ = std::min(odom_count_ + 1, kOdomHistory);
  if (s->vel()) {
    odom_v_ = s->vel()->x();
    odom_w_ = s->vel()->a();
  }
  if (scan_pending_) process_pending_scan(false);
}

bool Mcl::odometry_at(uint64_t t, desktop::Pose2& out) const {
  if (odom_count_ == 0) return false;
  auto at = [&](size_t i) -> const OdomSample& {  // i = 0: oldest
    return odom_[(odom_head_ + kOdomHistory - odom_count_ + i) % kOdomHistory];
  };
  const OdomSample& newest = at(odom_count_ - 1);
  if (t > newest.time_us) return false;
  if (t <= at(0).time_us) {
    out = at(0).pose;
    return true;
  }
  for (size_t i = odom_count_ - 1; i > 0; --i) {
    const OdomSample& a = at(i - 1);
    const OdomSample& b = at(i);
    if (a.time_us <= t && t <= b.time_us) {
      double f = b.time_us == a.time_us ? 1.0 : double(t - a.time_us) / double(b.time_us - a.time_us);
      out = desktop::interpolate(a.pose, b.pose, f);
      return true;
    }
  }
  return false;
}

void Mcl::on_scan(const wire::Message& data) {
  const wire::RangerScan* s = data.body_as_RangerScan();
  if (s == nullptr || s->ranges() == nullptr || !(s->scale() > 0) || !std::isfinite(s->scale()) ||
      !std::isfinite(s->min_angle()) || !std::isfinite(s->angular_res()) || s->angular_res() == 0) {
    if (++bad_scans_ <= 10) log_warn("%s: ignoring a scan without usable geometry or scale", name_.c_str());
    return;
  }
  scan_ranges_.resize(s->ranges()->size());
  for (size_t i = 0; i < scan_ranges_.size(); ++i)
    scan_ranges_[i] = float(s->ranges()->Get(uint32_t(i))) * s->scale();
  scan_view_.start_angle = s->min_angle();
  scan_view_.angular_res = s->angular_res();
  scan_view_.max_range = s->max_range() > 0 ? s->max_range() : 1e9;
  scan_view_.ranges = scan_ranges_;
  pending_landmarks_ = false;
  measured(wire::time_us(*data.header()));
}

void Mcl::on_landmarks(const wire::Message& data) {
  const wire::FiducialList* list = data.body_as_FiducialList();
  if (list == nullptr) return;
  seen_.clear();
  const auto* kinds = list->kinds();
  for (flatbuffers::uoffset_t i = 0; list->fiducials() && i < list->fiducials()->size(); ++i) {
    const wire::Fiducial* f = list->fiducials()->Get(i);
    const auto kind = kinds && i < kinds->size() ? wire::FiducialKind(kinds->Get(i)) : wire::FiducialKind::Generic;
    seen_.push_back({{kind, f->id()}, f->x(), f->y()});
  }
  pending_landmarks_ = true;
  measured(wire::time_us(*data.header()));
}

// A measurement (scan or landmarks) of `time_us` waits for the odometry of
// its instant; a newer one replaces it.
void Mcl::measured(uint64_t time_us) {
  scan_time_us_ = time_us;
  scan_pending_ = true;
  process_pending_scan(false);
  if (scan_pending_ && wait_timer_ == 0) wait_timer_ = node_->loop().start_timer(odom_wait_us_, 0, this);
}

void Mcl::process_pending_scan(bool force) {
  if (!scan_pending_) return;
  if (!filter_) {  // no map yet: nothing to localize against
    scan_pending_ = false;
    return;
  }
  desktop::Pose2 odom;
  if (!odometry_at(scan_time_us_, odom)) {
    if (!force || odom_count_ == 0) return;
    odom = odom_[(odom_head_ + kOdomHistory - 1) % kOdomHistory].pose;  // the newest we have
  }
  scan_pending_ = false;
  if (wait_timer_ != 0) {
    node_->loop().cancel_timer(wait_timer_);
    wait_timer_ = 0;
  }
  if (pending_landmarks_) {
    landmark_model_->set(seen_);
    filter_->update(odom, *landmark_model_, rng_);
  } else {
    filter_->update(odom, scan_view_, rng_);
  }
  publish(scan_time_us_);
}

void Mcl::publish(uint64_t time_us) {
  const auto& hyps = filter_->hypotheses();
  if (hyps.empty()) return;
  if (filter_->lost() != said_lost_) {
    said_lost_ = filter_->lost();
    if (said_lost_) {
      log_warn("%s: lost (the scans fit the belief far worse than before); searching", name_.c_str());
    } else {
      log_info("%s: localized again at (%.2f, %.2f, %.2f)", name_.c_str(), hyps.front().mean.x,
               hyps.front().mean.y, hyps.front().mean.a);
    }
  }
  {
    auto& b = node_->begin();
    hyp_out_.clear();
    for (const desktop::PoseHypothesis& h : hyps) {
      wire::Pose2d mean(float(h.mean.x), float(h.mean.y), float(h.mean.a));
      hyp_out_.emplace_back(mean, to_wire(h.cov), float(h.weight));
    }
    auto vec = b.CreateVectorOfStructs(hyp_out_);
    auto body = wire::CreateLocalizeState(b, vec, 0, time_us, filter_->lost());
    node_->publish(localize_, uint8_t(wire::LocalizeDataSub::Hypotheses), wire::Body::LocalizeState,
                   body.Union(), time_us);
  }
  if (position_ != kNoDevice) {
    auto& b = node_->begin();
    const desktop::PoseHypothesis& h = hyps.front();
    wire::Pose2d pose(float(h.mean.x), float(h.mean.y), float(h.mean.a));
    wire::Pose2d vel(odom_v_, 0, odom_w_);
    wire::Cov2d cov = to_wire(h.cov);
    auto body = wire::CreatePosition2dState(b, &pose, &vel, false, &cov);
    node_->publish(position_, uint8_t(wire::Position2dDataSub::State), wire::Body::Position2dState,
                   body.Union(), time_us);
  }
}

void Mcl::on_request(DeviceId device, const wire::Message& req, RequestToken token) {
  if (device != localize_) return Driver::on_request(device, req, token);
  switch (wire::LocalizeReqSub(req.header()->subtype())) {
    case wire::LocalizeReqSub::SetPose: {
      const wire::LocalizeSetPose* set = req.body_as_LocalizeSetPose();
      if (set == nullptr || set->mean() == nullptr || set->cov() == nullptr) {
        return node_->nack(token, wire::ErrorCode::BadArgument, "SetPose needs a mean and a covariance");
      }
      Eigen::Matrix3d cov = from_wire(*set->cov());
      desktop::Pose2 mean{set->mean()->x(), set->mean()->y(), set->mean()->a()};
      if (!std::isfinite(mean.x) || !std::isfinite(mean.y) || !std::isfinite(mean.a) || !cov.allFinite() ||
          cov(0, 0) < 0 || cov(1, 1) < 0 || cov(2, 2) < 0) {
        return node_->nack(token, wire::ErrorCode::BadArgument,
                           "SetPose: mean must be finite and the covariance's variances >= 0");
      }
      init_ = Init::Pose;
      init_pose_ = mean;
      init_cov_ = cov;
      apply_init();
      return node_->ack(token);
    }
    case wire::LocalizeReqSub::Global:
      init_ = Init::Global;
      apply_init();
      return node_->ack(token);
  }
  Driver::on_request(device, req, token);
}

extern const DriverEntry kEntry;
const DriverEntry kEntry{"mcl", []() -> Driver* { return new Mcl; }};

}  // namespace troupe::drivers::mcl
