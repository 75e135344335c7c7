// The p2os driver's devices: SIPs in, data out; commands and requests in,
// packets out. The connection's state machine is in p2os.cc.
#include <algorithm>
#include <cmath>

#include "drivers/p2os/p2os.h"
#include "runtime/log.h"
#include "runtime/node.h"

namespace troupe::drivers::p2os {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

}  // namespace

void P2os::handle_sip(std::span<const uint8_t> payload) {
  Sip sip;
  const char* why = nullptr;
  if (!parse_sip(payload, sip, &why)) {
    log_debug("%s: SIP of %zu bytes dropped: %s", name_.c_str(), payload.size(), why);
    return;
  }
  last_sip_us_ = node_->loop().now_us();
  switch (odometry_.update(sip)) {
    case Odometry::Update::JumpRejected:
      // Rare and worth knowing: the checksum let a corrupted SIP through.
      if (++jumps_rejected_ <= 5 || jumps_rejected_ % 100 == 0) {
        log_warn("%s: odometry jump of over %.0f mm in one SIP ignored (%u so far)", name_.c_str(),
                 Odometry::kMaxJumpMm, jumps_rejected_);
      }
      break;
    case Odometry::Update::JumpAccepted:
      log_warn("%s: the robot's odometry counters jumped and stayed; carrying on from their new values",
               name_.c_str());
      break;
    case Odometry::Update::ResetIgnored:
      log_warn("%s: the robot did not reset its odometry counters (SETO); reset on the driver side only",
               name_.c_str());
      break;
    default:
      break;
  }
  double left_mm_s = sip.left_vel * robot_->vel_conv, right_mm_s = sip.right_vel * robot_->vel_conv;
  vel_v_ = float(0.5 * (left_mm_s + right_mm_s) / 1000.0);
  vel_w_ = float(0.5 * (right_mm_s - left_mm_s) * robot_->diff_conv);
  stalled_ = sip.left_stall || sip.right_stall;
  publish_position();
  publish_power(sip);
  publish_bumpers(sip);

  bool fresh = false;
  for (size_t i = 0; i < sip.sonar_count; ++i) {
    const SonarReading& r = sip.sonar[i];
    if (r.index >= robot_->sonar_count) continue;
    double mm = std::min(r.range * robot_->range_conv, robot_->sonar_max_range * 1000.0);
    sonar_mm_[r.index] = uint16_t(std::lround(mm));
    sonar_seen_ |= 1u << r.index;
    fresh = true;
  }
  // The ring is published once every transducer has reported: before that
  // some ranges would be made up.
  uint32_t all = robot_->sonar_count >= 32 ? 0xFFFFFFFFu : (1u << robot_->sonar_count) - 1;
  if (fresh && sonar_seen_ == all) publish_sonar();
}

void P2os::publish_position() {
  if (position_ == kNoDevice) return;
  Pose p = odometry_.pose();
  auto& b = node_->begin();
  wire::Pose2d pose(float(p.x), float(p.y), float(p.a));
  wire::Pose2d vel(connected_ ? vel_v_ : 0, 0, connected_ ? vel_w_ : 0);
  // A base that is not under control (no connection) is reported stalled.
  auto body = wire::CreatePosition2dState(b, &pose, &vel, stalled_ || !connected_);
  node_->publish(position_, uint8_t(wire::Position2dDataSub::State), wire::Body::Position2dState,
                 body.Union());
}

void P2os::publish_sonar() {
  if (ranger_ == kNoDevice) return;
  auto& b = node_->begin();
  auto ranges = b.CreateVector(sonar_mm_, robot_->sonar_count);
  wire::RangerScanBuilder scan(b);
  scan.add_ranges(ranges);
  scan.add_scale(0.001f);
  scan.add_max_range(robot_->sonar_max_range);
  node_->publish(ranger_, uint8_t(wire::RangerDataSub::Scan), wire::Body::RangerScan, scan.Finish().Union());
}

void P2os::publish_power(const Sip& sip) {
  if (power_ == kNoDevice) return;
  auto& b = node_->begin();
  wire::PowerStateBuilder state(b);
  state.add_volts(sip.battery * 0.1f);
  node_->publish(power_, uint8_t(wire::PowerDataSub::State), wire::Body::PowerState, state.Finish().Union());
}

void P2os::publish_bumpers(const Sip& sip) {
  if (bumper_ == kNoDevice) return;
  auto& b = node_->begin();
  uint32_t pressed = uint32_t(sip.front_bumpers) | (uint32_t(sip.rear_bumpers) << 7);
  auto body = wire::CreateBumperState(b, pressed, 14);
  node_->publish(bumper_, uint8_t(wire::BumperDataSub::State), wire::Body::BumperState, body.Union());
}

void P2os::send_velocity() {
  uint64_t now = node_->loop().now_us();
  next_keepalive_us_ = now + pulse_us_;
  if (state_ != State::Running) return;
  if (!std::isfinite(target_v_) || !std::isfinite(target_w_)) target_v_ = target_w_ = 0;  // never encode NaN
  double v_mm_s = std::clamp(target_v_, -max_speed_, max_speed_) * 1000.0;
  double w = std::clamp(target_w_, -max_turn_, max_turn_);
  if (use_vel2_) {
    // Each wheel's share of the turn: w / DiffConvFactor, mm/s.
    double turn_mm_s = w / robot_->diff_conv;
    double div = robot_->vel2_divisor;
    send(vel2(int(std::lround((v_mm_s + turn_mm_s) / div)), int(std::lround((v_mm_s - turn_mm_s) / div))));
  } else {
    send(command_int(Command::Vel, int(std::lround(v_mm_s))));
    send(command_int(Command::RVel, int(std::lround(w * kRadToDeg))));
  }
}

void P2os::keep_alive() {
  // A moving robot is sent its velocity again (a command lost on the line
  // is then repaired); a still one a PULSE. Either feeds its watchdog.
  if (target_v_ != 0 || target_w_ != 0) return send_velocity();
  send(command(Command::Pulse));
  next_keepalive_us_ = node_->loop().now_us() + pulse_us_;
}

void P2os::on_command(DeviceId device, const wire::Message& command) {
  if (device != position_) return;
  if (const wire::Position2dVel* vel = command.body_as_Position2dVel(); vel && vel->vel()) {
    float v = vel->vel()->x(), w = vel->vel()->a();
    if (!std::isfinite(v) || !std::isfinite(w)) {
      log_warn("%s: velocity command with a non-finite value ignored", name_.c_str());
      return;
    }
    // Clamped when sent: the limits are the robot's, known once connected.
    target_v_ = v;
    target_w_ = w;
    last_command_us_ = node_->loop().now_us();
    send_velocity();
  } else if (command.body_type() == wire::Body::Position2dGoto && !goto_warned_) {
    goto_warned_ = true;
    log_warn("%s: Goto is not supported by the robot's firmware; send Vel commands", name_.c_str());
  }
}

void P2os::on_request(DeviceId device, const wire::Message& request, RequestToken token) {
  if (device == position_) return request_position(request, token);
  if (device == ranger_) return request_ranger(request, token);
  Driver::on_request(device, request, token);
}

void P2os::request_position(const wire::Message& req, RequestToken token) {
  using Sub = wire::Position2dReqSub;
  const RobotParams& robot = robot_ ? *robot_ : *(forced_model_ ? forced_model_ : find_robot("p3dx-sh"));
  switch (Sub(req.header()->subtype())) {
    case Sub::Geometry: {
      auto& b = node_->begin();
      wire::Pose3d pose(0, 0, 0, 0, 0, 0);
      wire::Vec3 size(robot.length, robot.width, 0);  // height not known
      auto body = wire::CreatePosition2dGeometry(b, &pose, &size);
      return node_->ack(token, wire::Body::Position2dGeometry, body.Union());
    }
    case Sub::MotorPower: {
      const wire::Switch* sw = req.body_as_Switch();
      if (sw == nullptr)
        return node_->nack(token, wire::ErrorCode::BadArgument, "motor power needs a Switch body");
      motors_on_ = sw->on();
      if (state_ == State::Running) send(command_int(Command::Enable, motors_on_ ? 1 : 0));
      return node_->ack(token);
    }
    case Sub::SetOdometry: {
      const wire::Position2dSetOdom* set = req.body_as_Position2dSetOdom();
      if (set == nullptr || set->pose() == nullptr) {
        return node_->nack(token, wire::ErrorCode::BadArgument, "set odometry needs a pose");
      }
      odometry_.set_pose({set->pose()->x(), set->pose()->y(), set->pose()->a()});
      publish_position();
      return node_->ack(token);
    }
    case Sub::ResetOdometry:
      odometry_.reset();
      if (state_ == State::Running) send(command(Command::SetO));
      publish_position();
      return node_->ack(token);
  }
  Driver::on_request(position_, req, token);
}

void P2os::request_ranger(const wire::Message& req, RequestToken token) {
  using Sub = wire::RangerReqSub;
  const RobotParams& robot = robot_ ? *robot_ : *(forced_model_ ? forced_model_ : find_robot("p3dx-sh"));
  switch (Sub(req.header()->subtype())) {
    case Sub::Geometry: {
      auto& b = node_->begin();
      wire::Pose3d elements[Sip::kMaxSonar];
      for (size_t i = 0; i < robot.sonar_count; ++i) {
        elements[i] = wire::Pose3d(robot.sonar[i].x, robot.sonar[i].y, 0, 0, 0, robot.sonar[i].a);
      }
      auto poses = b.CreateVectorOfStructs(elements, robot.sonar_count);
      wire::Pose3d pose(0, 0, 0, 0, 0, 0);
      wire::Vec3 size(0, 0, 0);
      auto body = wire::CreateRangerGeometry(b, &pose, &size, poses);
      return node_->ack(token, wire::Body::RangerGeometry, body.Union());
    }
    case Sub::GetConfig: {
      auto& b = node_->begin();
      // A ring of separate transducers: no scan angles, millimetre ranges.
      auto body = wire::CreateRangerConfig(b, 0, 0, 0, 0, robot.sonar_max_range, 0.001f, 0);
      return node_->ack(token, wire::Body::RangerConfig, body.Union());
    }
    case Sub::Power: {
      const wire::Switch* sw = req.body_as_Switch();
      if (sw == nullptr)
        return node_->nack(token, wire::ErrorCode::BadArgument, "sonar power needs a Switch body");
      sonar_on_ = sw->on();
      if (state_ == State::Running) send(command_int(Command::Sonar, sonar_on_ ? 1 : 0));
      return node_->ack(token);
    }
    case Sub::SetConfig:
      return node_->nack(token, wire::ErrorCode::Unsupported, "the sonar ring's configuration is fixed");
  }
  Driver::on_request(ranger_, req, token);
}

}  // namespace troupe::drivers::p2os
