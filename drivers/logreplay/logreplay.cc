#include "drivers/logreplay/logreplay.h"

#include <algorithm>
#include <cmath>

#include "runtime/log.h"
#include "runtime/node.h"
#include "wire/address.h"

namespace troupe::drivers::logreplay {

using desktop::ReplaySample;

bool LogReplay::setup(Node& node, const DriverSetup& setup, std::string& error) {
  OptionsView<Options> opt(setup);
  for (DeviceId d : setup.provides) {
    auto iface = wire::Interface(node.address(d).iface());
    if (iface == wire::Interface::Position2d && odom_ == kNoDevice) {
      odom_ = d;
    } else if (iface == wire::Interface::Position2d && truth_ == kNoDevice) {
      truth_ = d;
    } else if (iface == wire::Interface::Ranger && ranger_ == kNoDevice) {
      ranger_ = d;
    } else {
      error = "provides " + wire::format_address(node.address(d)) +
              ": logreplay serves one or two position2d (odometry, ground truth) and one ranger";
      return false;
    }
  }
  if (opt->file() == nullptr || opt->file()->size() == 0) {
    error = "option \"file\" (the CARMEN log) is missing";
    return false;
  }
  if (!(opt->speed() > 0 && opt->speed() <= 1000)) {
    error = "option \"speed\" must be in (0, 1000]";
    return false;
  }
  if (!(opt->start_delay() >= 0 && opt->start_delay() < 3600)) {
    error = "option \"start_delay\" must be in [0, 3600) s";
    return false;
  }
  speed_ = opt->speed();
  loop_ = opt->loop();
  desktop::CarmenOptions copt;
  copt.flaser_fov = opt->flaser_fov();
  copt.flaser_start_angle = opt->flaser_start_angle();
  copt.flaser_max_range = opt->flaser_max_range();
  if (!desktop::read_carmen(opt->file()->str(), log_, error, copt)) return false;
  for (const std::string& e : log_.errors) log_warn("%s: %s (line skipped)", setup.name.c_str(), e.c_str());
  if (log_.error_count > log_.errors.size()) {
    log_warn("%s: %zu more malformed lines skipped", setup.name.c_str(),
             log_.error_count - log_.errors.size());
  }

  desktop::TimelineOptions topt;
  topt.odometry = opt->odometry() == OdometrySource::Corrected ? desktop::OdometrySource::Corrected
                                                               : desktop::OdometrySource::Log;
  topt.ground_truth = truth_ != kNoDevice;
  topt.noise.scale_sigma = opt->scale_sigma();
  topt.noise.turn_bias_sigma = opt->turn_bias_sigma();
  topt.noise.trans_per_m = opt->trans_per_m();
  topt.noise.rot_per_rad = opt->rot_per_rad();
  topt.noise.rot_per_m = opt->rot_per_m();
  topt.noise.slip_probability = opt->slip_probability();
  topt.noise.slip_max_extra = opt->slip_max_extra();
  desktop::Rng rng(opt->seed());
  timeline_ = desktop::build_timeline(log_, topt, rng);
  if (timeline_.samples.empty()) {
    error = opt->file()->str() + ": no ODOM, FLASER, ROBOTLASER1 or TRUEPOS records to play (" +
            std::to_string(log_.line_count) + " lines, " + std::to_string(log_.error_count) + " malformed)";
    return false;
  }
  if (timeline_.clamped > 0) {
    log_info(
        "%s: %zu records are stamped earlier than the record before them; they play at that record's time",
        setup.name.c_str(), timeline_.clamped);
  }
  log_info("%s: %zu odometry, %zu scans, %zu true poses over %.1f s of log", setup.name.c_str(),
           log_.odometry.size(), log_.scans.size(), log_.true_poses.size(),
           timeline_.samples.back().time_s - timeline_.samples.front().time_s);
  start_us_ = node.now_us() + uint64_t(opt->start_delay() * 1e6);
  schedule();
  return true;
}

uint64_t LogReplay::due_us(size_t i) const {
  double dt = (timeline_.samples[i].time_s - timeline_.samples.front().time_s) / speed_;
  return start_us_ + uint64_t(std::llround(dt * 1e6));
}

void LogReplay::schedule() {
  uint64_t now = node_->now_us(), due = due_us(next_);
  node_->loop().start_timer(due > now ? due - now : 0, 0, this);
}

void LogReplay::on_timer(TimerId) {
  uint64_t now = node_->now_us();
  // Everything due by now, in order, each stamped with its own due time.
  while (next_ < timeline_.samples.size() && due_us(next_) <= now) {
    publish(timeline_.samples[next_], due_us(next_));
    ++next_;
  }
  if (next_ == timeline_.samples.size()) {
    if (!loop_) {
      log_info("logreplay: end of log (%zu samples played)", next_);
      return;
    }
    next_ = 0;
    start_us_ = now;
  }
  schedule();
}

void LogReplay::publish(const ReplaySample& s, uint64_t time_us) {
  switch (s.kind) {
    case ReplaySample::Kind::Odometry:
    case ReplaySample::Kind::GroundTruth: {
      DeviceId dev = s.kind == ReplaySample::Kind::Odometry ? odom_ : truth_;
      if (dev == kNoDevice) return;
      auto& b = node_->begin();
      wire::Pose2d pose(float(s.pose.x), float(s.pose.y), float(s.pose.a));
      wire::Pose2d vel(float(s.tv), 0, float(s.rv));
      auto body = wire::CreatePosition2dState(b, &pose, &vel, false);
      return node_->publish(dev, uint8_t(wire::Position2dDataSub::State), wire::Body::Position2dState,
                            body.Union(), time_us);
    }
    case ReplaySample::Kind::Scan: {
      if (ranger_ == kNoDevice) return;
      const desktop::LaserReading& l = log_.scans[s.scan];
      // Millimetres while they fit in 16 bits, centimetres beyond 65 m.
      float scale = l.max_range < 65.0 ? 0.001f : 0.01f;
      ranges_.resize(l.ranges.size());
      for (size_t i = 0; i < l.ranges.size(); ++i) {
        double r = std::min<double>(l.ranges[i], l.max_range);
        ranges_[i] = uint16_t(std::clamp(std::lround(r / scale), 0L, 65535L));
      }
      auto& b = node_->begin();
      auto ranges = b.CreateVector(ranges_);
      auto body = wire::CreateRangerScan(b, ranges, scale, float(l.start_angle), float(l.angular_res),
                                         float(l.max_range));
      return node_->publish(ranger_, uint8_t(wire::RangerDataSub::Scan), wire::Body::RangerScan, body.Union(),
                            time_us);
    }
  }
}

void LogReplay::on_request(DeviceId device, const wire::Message& req, RequestToken token) {
  uint8_t sub = req.header()->subtype();
  if (device == ranger_ && sub == uint8_t(wire::RangerReqSub::Geometry)) {
    auto& b = node_->begin();
    wire::Pose3d pose(0, 0, 0, 0, 0, 0);
    wire::Vec3 size(0.15f, 0.15f, 0.2f);
    auto body = wire::CreateRangerGeometry(b, &pose, &size);
    return node_->ack(token, wire::Body::RangerGeometry, body.Union());
  }
  if (device == ranger_ && sub == uint8_t(wire::RangerReqSub::GetConfig)) {
    if (log_.scans.empty()) return node_->nack(token, wire::ErrorCode::DeviceFailed, "the log has no scans");
    const desktop::LaserReading& l = log_.scans.front();
    double last = l.start_angle + double(l.ranges.size() - 1) * l.angular_res;
    double rate = log_.scans.size() > 1 ? double(log_.scans.size() - 1) /
                                              std::max(1e-9, log_.scans.back().time_s - l.time_s) * speed_
                                        : 0.0;
    auto& b = node_->begin();
    auto body = wire::CreateRangerConfig(b, float(l.start_angle), float(last), float(l.angular_res), 0.0f,
                                         float(l.max_range), 0.01f, float(rate));
    return node_->ack(token, wire::Body::RangerConfig, body.Union());
  }
  if ((device == odom_ || device == truth_) && sub == uint8_t(wire::Position2dReqSub::Geometry)) {
    auto& b = node_->begin();
    wire::Pose3d pose(0, 0, 0, 0, 0, 0);
    wire::Vec3 size(0.5f, 0.4f, 0.3f);
    auto body = wire::CreatePosition2dGeometry(b, &pose, &size);
    return node_->ack(token, wire::Body::Position2dGeometry, body.Union());
  }
  Driver::on_request(device, req, token);
}

extern const DriverEntry kEntry;
const DriverEntry kEntry{"logreplay", []() -> Driver* { return new LogReplay; }};

}  // namespace troupe::drivers::logreplay
