#include "drivers/kinematic/kinematic.h"

#include <algorithm>
#include <cmath>

#include "runtime/node.h"
#include "wire/geometry.h"

namespace troupe::drivers::kinematic {
namespace {

float wrap_angle(float a) { return float(geometry::wrap_angle(a)); }

float approach(float current, float target, float max_change) {
  return current + std::clamp(target - current, -max_change, max_change);
}

}  // namespace

void step(Base& b, const Limits& lim, float dt) {
  float tv = std::clamp(b.target_v, -lim.max_speed, lim.max_speed);
  float tw = std::clamp(b.target_w, -lim.max_turn_rate, lim.max_turn_rate);
  b.v = approach(b.v, tv, lim.max_accel * dt);
  b.w = approach(b.w, tw, lim.max_turn_accel * dt);
  // Exact integration along the arc; a straight line when hardly turning.
  if (std::fabs(b.w) < 1e-6f) {
    b.x += b.v * dt * std::cos(b.a);
    b.y += b.v * dt * std::sin(b.a);
  } else {
    float r = b.v / b.w;
    float a1 = b.a + b.w * dt;
    b.x += r * (std::sin(a1) - std::sin(b.a));
    b.y -= r * (std::cos(a1) - std::cos(b.a));
  }
  b.a = wrap_angle(b.a + b.w * dt);
}

bool Kinematic::setup(Node& node, const DriverSetup& setup, std::string& error) {
  if (setup.provides.size() != 1 || node.address(setup.provides[0]).iface() != uint16_t(wire::Interface::Position2d)) {
    error = "kinematic provides exactly one position2d device";
    return false;
  }
  device_ = setup.provides[0];
  OptionsView<Options> opt(setup);
  if (!(opt->rate_hz() > 0 && opt->rate_hz() <= 1000)) {
    error = "rate_hz must be in (0, 1000] Hz";
    return false;
  }
  if (opt->max_speed() < 0 || opt->max_turn_rate() < 0 || opt->max_accel() <= 0 || opt->max_turn_accel() <= 0) {
    error = "speed limits must be >= 0 and acceleration limits > 0";
    return false;
  }
  limits_ = {opt->max_speed(), opt->max_turn_rate(), opt->max_accel(), opt->max_turn_accel()};
  base_.x = opt->initial_x();
  base_.y = opt->initial_y();
  base_.a = wrap_angle(opt->initial_a());
  length_ = opt->length();
  width_ = opt->width();
  command_timeout_us_ = uint64_t(opt->command_timeout_ms()) * 1000u;
  period_us_ = uint64_t(1e6f / opt->rate_hz());
  last_step_us_ = node.now_us();
  if (node.loop().start_timer(period_us_, period_us_, this) == 0) {
    error = "no timer left";
    return false;
  }
  return true;
}

void Kinematic::on_command(DeviceId, const wire::Message& cmd) {
  last_command_us_ = node_->now_us();
  if (const wire::Position2dVel* vel = cmd.body_as_Position2dVel(); vel && vel->vel()) {
    has_goal_ = false;
    base_.target_v = vel->vel()->x();
    base_.target_w = vel->vel()->a();
  } else if (const wire::Position2dGoto* go = cmd.body_as_Position2dGoto(); go && go->pose()) {
    has_goal_ = true;
    goal_ = *go->pose();
    goal_max_v_ = go->max_vel() && go->max_vel()->x() > 0 ? go->max_vel()->x() : limits_.max_speed;
    goal_max_w_ = go->max_vel() && go->max_vel()->a() > 0 ? go->max_vel()->a() : limits_.max_turn_rate;
  }
}

void Kinematic::steer_to_goal() {
  // Turn towards the goal, drive with the heading error shrinking the speed,
  // then turn to the goal's heading. Gains give ~1 s time constants.
  float dx = goal_.x() - base_.x, dy = goal_.y() - base_.y;
  float dist = std::hypot(dx, dy);
  if (dist > 0.02f) {
    float bearing = wrap_angle(std::atan2(dy, dx) - base_.a);
    base_.target_w = std::clamp(2.0f * bearing, -goal_max_w_, goal_max_w_);
    base_.target_v = std::fabs(bearing) > 0.5f ? 0.0f : std::min(goal_max_v_, dist) * std::cos(bearing);
  } else {
    float turn = wrap_angle(goal_.a() - base_.a);
    base_.target_v = 0;
    base_.target_w = std::fabs(turn) > 0.01f ? std::clamp(2.0f * turn, -goal_max_w_, goal_max_w_) : 0.0f;
    if (base_.target_w == 0) has_goal_ = false;
  }
}

void Kinematic::on_timer(TimerId) {
  uint64_t now = node_->now_us();
  float dt = float(now - last_step_us_) * 1e-6f;
  last_step_us_ = now;
  if (command_timeout_us_ > 0 && now - last_command_us_ > command_timeout_us_) {
    base_.target_v = base_.target_w = 0;
    has_goal_ = false;
  }
  if (has_goal_) steer_to_goal();
  if (!motors_on_) base_.target_v = base_.target_w = 0;
  step(base_, limits_, dt);
  publish();
}

void Kinematic::publish() {
  auto& b = node_->begin();
  wire::Pose2d pose(base_.x, base_.y, base_.a);
  wire::Pose2d vel(base_.v, 0, base_.w);
  auto body = wire::CreatePosition2dState(b, &pose, &vel, false);
  node_->publish(device_, uint8_t(wire::Position2dDataSub::State), wire::Body::Position2dState, body.Union());
}

void Kinematic::on_request(DeviceId device, const wire::Message& req, RequestToken token) {
  using Sub = wire::Position2dReqSub;
  switch (Sub(req.header()->subtype())) {
    case Sub::Geometry: {
      auto& b = node_->begin();
      wire::Pose3d pose(0, 0, 0, 0, 0, 0);
      wire::Vec3 size(length_, width_, 0.2f);
      auto body = wire::CreatePosition2dGeometry(b, &pose, &size);
      return node_->ack(token, wire::Body::Position2dGeometry, body.Union());
    }
    case Sub::MotorPower: {
      const wire::Switch* sw = req.body_as_Switch();
      if (sw == nullptr) return node_->nack(token, wire::ErrorCode::BadArgument, "motor power needs a Switch body");
      motors_on_ = sw->on();
      return node_->ack(token);
    }
    case Sub::SetOdometry: {
      const wire::Position2dSetOdom* set = req.body_as_Position2dSetOdom();
      if (set == nullptr || set->pose() == nullptr) {
        return node_->nack(token, wire::ErrorCode::BadArgument, "set odometry needs a pose");
      }
      base_.x = set->pose()->x();
      base_.y = set->pose()->y();
      base_.a = wrap_angle(set->pose()->a());
      has_goal_ = false;
      return node_->ack(token);
    }
    case Sub::ResetOdometry:
      base_.x = base_.y = base_.a = 0;
      has_goal_ = false;
      return node_->ack(token);
  }
  Driver::on_request(device, req, token);
}

extern const DriverEntry kEntry;
const DriverEntry kEntry{"kinematic", []() -> Driver* { return new Kinematic; }};

}  // namespace troupe::drivers::kinematic
