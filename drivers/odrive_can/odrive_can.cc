#include "drivers/odrive_can/odrive_can.h"

#include <sys/epoll.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>

#include "drivers/odrive_can/can_io.h"
#include "runtime/log.h"
#include "runtime/node.h"
#include "runtime/node_config.h"

namespace troupe::drivers::odrive_can {

using cansimple::AxisState;
using cansimple::Cmd;

namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr int kFramesPerEvent = 64;  // then let other descriptors run
constexpr uint64_t kReopenFirstUs = 500000;
constexpr uint64_t kReopenMaxUs = 8000000;

}  // namespace

const char* state_name(State s) {
  switch (s) {
    case State::Connecting:
      return "connecting";
    case State::Arming:
      return "arming";
    case State::Running:
      return "running";
    case State::MotorsOff:
      return "motors off";
    case State::Fault:
      return "fault";
  }
  return "?";
}

OdriveCan::~OdriveCan() {
  // After a failed setup shutdown() never runs: leave nothing in the loop
  // that points here. (The node's loop outlives its drivers.)
  if (node_ != nullptr) {
    for (TimerId t : {tick_timer_, power_timer_, reopen_timer_}) {
      if (t) node_->loop().cancel_timer(t);
    }
    if (fd_ >= 0) node_->loop().unwatch(fd_);
  }
  if (own_fd_ && fd_ >= 0) close(fd_);
}

void OdriveCan::bus_down() {
  // The socket survives an interface going down and works again once it is
  // up: heartbeats coming back then lead out of Fault as after any silence.
  if (state_ != State::Fault) fault("CAN interface %s is down", given_fd_ >= 0 ? "(given)" : ifname_.c_str());
}

void OdriveCan::lose_bus(const char* what, int err) {
  if (fd_ < 0) return;
  node_->loop().unwatch(fd_);
  if (own_fd_) close(fd_);
  fd_ = -1;
  for (Axis& a : axes_) a.tracker.reset();
  fault("CAN bus lost (%s%s%s)", what, err ? ": " : "", err ? strerror(err) : "");
  if (given_fd_ < 0) {
    reopen_delay_us_ = reopen_delay_us_ ? std::min(reopen_delay_us_ * 2, kReopenMaxUs) : kReopenFirstUs;
    reopen_timer_ = node_->loop().start_timer(reopen_delay_us_, 0, this);
  } else {
    log_error("%s: the CAN descriptor it was given is gone; the driver stays stopped", name_.c_str());
  }
}

// ---- Frames in ---------------------------------------------------------------

void OdriveCan::on_fd(int fd, uint32_t events) {
  if (fd != fd_) return;
  for (int i = 0; i < kFramesPerEvent; ++i) {
    can_frame f;
    int err = 0;
    switch (cansimple::read_frame(fd_, f, err)) {
      case cansimple::IoResult::Frame:
        handle_frame(f);
        break;
      case cansimple::IoResult::WouldBlock:
        if (events & (EPOLLHUP | EPOLLERR)) lose_bus("hang-up", 0);
        return;
      case cansimple::IoResult::Rejected:
      case cansimple::IoResult::Short:
        warn_limited("%s: a read gave %d bytes, not one %zu-byte can_frame: ignored", name_.c_str(), err,
                     sizeof(can_frame));
        break;
      case cansimple::IoResult::Down:
        return bus_down();
      case cansimple::IoResult::Closed:
        return lose_bus(err ? "read" : "the other end closed", err);
    }
    if (fd_ < 0) return;
  }
}

void OdriveCan::handle_frame(const can_frame& f) {
  if (f.can_id & CAN_ERR_FLAG) {
    warn_limited("%s: CAN error frame, class 0x%08x", name_.c_str(), unsigned(f.can_id & CAN_ERR_MASK));
    return;
  }
  // A descriptor without kernel filters (a socketpair) carries everything:
  // the checks the filters would have made are repeated here.
  if (!cansimple::is_plain_data(f)) return;
  uint8_t node = cansimple::node_of(f.can_id);
  Axis* axis = node == axes_[0].node_id ? &axes_[0] : node == axes_[1].node_id ? &axes_[1] : nullptr;
  if (axis == nullptr) return;
  if (f.len > CAN_MAX_DLEN) {
    warn_limited("%s: %s axis (node %u): frame 0x%03x with DLC %u > 8: ignored", name_.c_str(), axis->side,
                 node, unsigned(f.can_id), unsigned(f.len));
    return;
  }
  auto short_frame = [&](const char* what, int need) {
    warn_limited("%s: %s axis (node %u): %s with %u data bytes (needs %d): ignored", name_.c_str(),
                 axis->side, node, what, unsigned(f.len), need);
  };
  switch (Cmd(cansimple::cmd_of(f.can_id))) {
    case Cmd::Heartbeat: {
      cansimple::Heartbeat hb;
      if (!cansimple::parse(f, hb)) return short_frame("heartbeat", 5);
      return on_heartbeat(*axis, hb);
    }
    case Cmd::GetEncoderEstimates: {
      cansimple::EncoderEstimates est;
      if (!cansimple::parse(f, est)) return short_frame("encoder estimates", 8);
      return on_estimates(*axis, est);
    }
    case Cmd::GetBusVoltageCurrent: {
      cansimple::BusVoltageCurrent bus;
      if (!cansimple::parse(f, bus)) return short_frame("bus voltage", 8);
      return on_bus_voltage(bus);
    }
    default:
      return;  // commands other hosts send to our axes, replies we did not ask for
  }
}

void OdriveCan::on_heartbeat(Axis& axis, const cansimple::Heartbeat& hb) {
  axis.heartbeats++;
  axis.last_heartbeat_us = node_->loop().now_us();
  axis.last = hb;
  if (state_ == State::Running && (hb.axis_error != 0 || hb.state != AxisState::ClosedLoopControl)) {
    if (hb.axis_error & cansimple::axis_error::kEstopRequested) latched_ = true;
    fault("%s axis (node %u) error 0x%x %s in state %s", axis.side, axis.node_id, unsigned(hb.axis_error),
          cansimple::axis_error_name(hb.axis_error), cansimple::axis_state_name(hb.state));
  } else if (state_ == State::Arming && axis_armed(axes_[0]) && axis_armed(axes_[1])) {
    enter(State::Running);
  }
}

void OdriveCan::on_estimates(Axis& axis, const cansimple::EncoderEstimates& est) {
  double delta = 0;
  auto step = axis.tracker.update(est.pos_turns, node_->loop().now_us(), delta);
  if (step == PositionTracker::Step::Refused) {
    axis.refused_steps++;
    warn_limited(
        "%s: %s axis (node %u): position jumped to %.3f turns, faster than the wheel can turn: "
        "odometry resumes from there",
        name_.c_str(), axis.side, axis.node_id, double(est.pos_turns));
  }
  if (std::isfinite(est.vel_turns_s)) axis.vel_turns_s = est.vel_turns_s;
  axis.pending_m += (axis.invert ? -delta : delta) * kTwoPi * double(geometry_.wheel_radius);
  axis.fresh = true;
  // Integrate pairs: the axes report in step, and a lone wheel's motion would
  // otherwise read as turning.
  if (axes_[0].fresh && axes_[1].fresh) {
    integrate(odom_, axes_[0].pending_m, axes_[1].pending_m, geometry_.track_width);
    for (Axis& a : axes_) {
      a.pending_m = 0;
      a.fresh = false;
    }
  }
}

void OdriveCan::on_bus_voltage(const cansimple::BusVoltageCurrent& bus) {
  if (power_ == kNoDevice || !std::isfinite(bus.volts)) return;
  auto& b = node_->begin();
  wire::PowerStateBuilder ps(b);
  ps.add_volts(bus.volts);
  node_->publish(power_, uint8_t(wire::PowerDataSub::State), wire::Body::PowerState, ps.Finish().Union());
}

// ---- Frames out --------------------------------------------------------------

void OdriveCan::send(const can_frame& f) {
  if (fd_ < 0) return;
  int err = 0;
  switch (cansimple::write_frame(fd_, f, err)) {
    case cansimple::IoResult::Frame:
      return;
    case cansimple::IoResult::WouldBlock:
      warn_limited("%s: CAN transmit queue full: frame 0x%03x dropped", name_.c_str(), unsigned(f.can_id));
      return;
    case cansimple::IoResult::Short:
      warn_limited("%s: CAN write took %d of %zu bytes", name_.c_str(), err, sizeof f);
      return;
    case cansimple::IoResult::Rejected:
      warn_limited("%s: the kernel refused frame 0x%03x", name_.c_str(), unsigned(f.can_id));
      return;
    case cansimple::IoResult::Down:
      return bus_down();
    case cansimple::IoResult::Closed:
      return lose_bus("write", err);
  }
}

void OdriveCan::send_both_stop(bool idle) {
  for (Axis& a : axes_) {
    send(cansimple::set_input_vel_frame(a.node_id, {0, 0}));
    if (idle) send(cansimple::set_axis_state_frame(a.node_id, AxisState::Idle));
  }
}

void OdriveCan::send_arming(Axis& a) {
  cansimple::InputMode input =
      velocity_ramp_ ? cansimple::InputMode::VelRamp : cansimple::InputMode::Passthrough;
  send(cansimple::empty_frame(a.node_id, Cmd::ClearErrors));
  send(cansimple::set_controller_modes_frame(a.node_id, {cansimple::ControlMode::Velocity, input}));
  send(cansimple::set_limits_frame(a.node_id, {max_wheel_turns_s_, current_limit_}));
  send(cansimple::set_input_vel_frame(a.node_id, {0, 0}));
  send(cansimple::set_axis_state_frame(a.node_id, AxisState::ClosedLoopControl));
}

// ---- State machine -----------------------------------------------------------

bool OdriveCan::both_alive(uint64_t now) const {
  return axes_[0].alive(now, heartbeat_timeout_us_) && axes_[1].alive(now, heartbeat_timeout_us_);
}

bool OdriveCan::axis_armed(const Axis& a) const {
  // Only a heartbeat sent after the request counts: older ones still in
  // flight show the state before it.
  int i = &a == &axes_[0] ? 0 : 1;
  return a.heartbeats > arm_marks_[i] && a.last.axis_error == 0 &&
         a.last.state == AxisState::ClosedLoopControl;
}

void OdriveCan::enter(State s) {
  uint64_t now = node_->loop().now_us();
  if (s != state_) {
    log_info("%s: %s -> %s", name_.c_str(), state_name(state_), state_name(s));
  }
  state_ = s;
  state_since_us_ = now;
  switch (s) {
    case State::Arming:
      for (int i = 0; i < 2; ++i) {
        arm_marks_[i] = axes_[i].heartbeats;
        send_arming(axes_[i]);
      }
      break;
    case State::Running:
      stalled_ = false;
      latched_ = false;
      fault_text_.clear();
      running_since_us_ = now;
      break;
    case State::MotorsOff:
      send_both_stop(true);
      break;
    case State::Fault:
      send_both_stop(true);
      stalled_ = true;
      break;
    case State::Connecting:
      break;
  }
}

void OdriveCan::fault(const char* fmt, ...) {
  char text[160];
  va_list args;
  va_start(args, fmt);
  vsnprintf(text, sizeof text, fmt, args);
  va_end(args);
  if (state_ == State::Fault && fault_text_ == text) return;  // nothing new
  uint64_t now = node_->loop().now_us();
  // Back off while recovery keeps failing; a base that ran a while since the
  // last fault starts again from the first delay.
  if (retry_wait_us_ == 0 || (state_ == State::Running && now - running_since_us_ > retry_max_us_)) {
    retry_wait_us_ = retry_delay_us_;
  } else {
    retry_wait_us_ = std::min(retry_wait_us_ * 2, retry_max_us_);
  }
  if (fault_text_ != text || state_ != State::Fault) log_warn("%s: stopped: %s", name_.c_str(), text);
  fault_text_ = text;
  enter(State::Fault);
}

void OdriveCan::tick() {
  uint64_t now = node_->loop().now_us();
  auto silent_axis = [&]() -> Axis* {
    for (Axis& a : axes_) {
      if (!a.alive(now, heartbeat_timeout_us_)) return &a;
    }
    return nullptr;
  };
  switch (state_) {
    case State::Connecting:
      if (both_alive(now)) {
        enter(State::Arming);
      } else if (now - state_since_us_ > heartbeat_timeout_us_ && fd_ >= 0) {
        Axis* a = silent_axis();
        fault("no heartbeat from the %s axis (node %u)", a->side, a->node_id);
      }
      break;
    case State::Arming:
    case State::Running:
      if (Axis* quiet = silent_axis()) {
        uint64_t since = quiet->heartbeats ? quiet->last_heartbeat_us : state_since_us_;
        fault("%s axis (node %u) silent: no heartbeat for %.1f s", quiet->side, quiet->node_id,
              double(now - since) * 1e-6);
      } else if (state_ == State::Arming && now - state_since_us_ > arm_timeout_us_) {
        const Axis& slow = axis_armed(axes_[0]) ? axes_[1] : axes_[0];
        fault("%s axis (node %u) did not enter closed loop: state %s, error 0x%x %s", slow.side, slow.node_id,
              cansimple::axis_state_name(slow.last.state), unsigned(slow.last.axis_error),
              cansimple::axis_error_name(slow.last.axis_error));
      }
      break;
    case State::Fault:
      if (!latched_ && fd_ >= 0 && both_alive(now) && now - state_since_us_ >= retry_wait_us_) {
        log_info("%s: both axes heartbeating: recovering", name_.c_str());
        enter(State::Arming);
      }
      break;
    case State::MotorsOff:
      break;
  }

  if (command_timeout_us_ > 0 && now - last_command_us_ > command_timeout_us_) target_v_ = target_w_ = 0;
  // Every tick sends a velocity to both axes: it is what the watchdog on the
  // ODrive waits for, and zero holds a stopped axis still.
  WheelTurnRates rates;
  if (state_ == State::Running) rates = wheel_rates(target_v_, target_w_, geometry_, max_wheel_turns_s_);
  send(cansimple::set_input_vel_frame(axes_[0].node_id, {rates.left, 0}));
  send(cansimple::set_input_vel_frame(axes_[1].node_id, {rates.right, 0}));
  publish_position();
}

void OdriveCan::publish_position() {
  WheelTurnRates measured{axes_[0].vel_turns_s, axes_[1].vel_turns_s};
  float v = 0, w = 0;
  body_velocity(measured, geometry_, v, w);
  auto& b = node_->begin();
  flatbuffers::Offset<flatbuffers::String> why;
  if (stalled_ && !fault_text_.empty()) why = b.CreateString(fault_text_);
  wire::Pose2d pose(float(odom_.x), float(odom_.y), float(odom_.a));
  wire::Pose2d vel(v, 0, w);
  wire::Position2dStateBuilder ps(b);
  ps.add_pose(&pose);
  ps.add_vel(&vel);
  ps.add_stall(stalled_);
  if (!why.IsNull()) ps.add_fault(why);
  node_->publish(position_, uint8_t(wire::Position2dDataSub::State), wire::Body::Position2dState,
                 ps.Finish().Union());
}

void OdriveCan::on_timer(TimerId id) {
  if (id == tick_timer_) return tick();
  if (id == power_timer_) {
    // Ask an axis that is alive; either sees the same bus.
    uint64_t now = node_->loop().now_us();
    const Axis& a = axes_[0].alive(now, heartbeat_timeout_us_) ? axes_[0] : axes_[1];
    return send(cansimple::get_request_frame(a.node_id, Cmd::GetBusVoltageCurrent));
  }
  if (id == reopen_timer_) {
    reopen_timer_ = 0;
    std::string error;
    if (open_bus(error)) {
      log_info("%s: CAN interface %s open again", name_.c_str(), ifname_.c_str());
      reopen_delay_us_ = 0;
    } else {
      reopen_delay_us_ = std::min(reopen_delay_us_ * 2, kReopenMaxUs);
      warn_limited("%s: reopening %s: %s (next try in %.1f s)", name_.c_str(), ifname_.c_str(), error.c_str(),
                   double(reopen_delay_us_) * 1e-6);
      reopen_timer_ = node_->loop().start_timer(reopen_delay_us_, 0, this);
    }
  }
}

// ---- Commands and requests -----------------------------------------------------

void OdriveCan::on_command(DeviceId, const wire::Message& cmd) {
  if (const wire::Position2dVel* vel = cmd.body_as_Position2dVel(); vel && vel->vel()) {
    last_command_us_ = node_->loop().now_us();
    float v = vel->vel()->x(), w = vel->vel()->a();
    if (!std::isfinite(v) || !std::isfinite(w)) {
      warn_limited("%s: velocity command with a non-finite value: stopping", name_.c_str());
      v = w = 0;
    }
    target_v_ = std::clamp(v, -max_speed_, max_speed_);
    target_w_ = std::clamp(w, -max_turn_rate_, max_turn_rate_);
  } else if (!warned_goto_) {
    warned_goto_ = true;
    log_warn("%s: only velocity commands are supported; others are ignored", name_.c_str());
  }
}

void OdriveCan::on_request(DeviceId device, const wire::Message& req, RequestToken token) {
  using Sub = wire::Position2dReqSub;
  if (device != position_) return Driver::on_request(device, req, token);
  switch (Sub(req.header()->subtype())) {
    case Sub::Geometry: {
      auto& b = node_->begin();
      wire::Pose3d pose(0, 0, 0, 0, 0, 0);
      wire::Vec3 size(length_, width_, 2 * geometry_.wheel_radius);
      auto body = wire::CreatePosition2dGeometry(b, &pose, &size);
      return node_->ack(token, wire::Body::Position2dGeometry, body.Union());
    }
    case Sub::MotorPower: {
      const wire::Switch* sw = req.body_as_Switch();
      if (sw == nullptr)
        return node_->nack(token, wire::ErrorCode::BadArgument, "motor power needs a Switch body");
      if (!sw->on()) {
        // The command is kept, as the kinematic driver keeps it: power on
        // again and the base does what it was last told.
        if (state_ != State::MotorsOff) enter(State::MotorsOff);
        return node_->ack(token);
      }
      if (fd_ < 0) return node_->nack(token, wire::ErrorCode::DeviceFailed, "the CAN bus is down");
      if (state_ == State::MotorsOff || state_ == State::Fault) {
        latched_ = false;
        retry_wait_us_ = 0;
        enter(both_alive(node_->loop().now_us()) ? State::Arming : State::Fault);
      }
      return node_->ack(token);
    }
    case Sub::SetOdometry: {
      const wire::Position2dSetOdom* set = req.body_as_Position2dSetOdom();
      if (set == nullptr || set->pose() == nullptr) {
        return node_->nack(token, wire::ErrorCode::BadArgument, "set odometry needs a pose");
      }
      odom_ = {set->pose()->x(), set->pose()->y(), std::remainder(double(set->pose()->a()), kTwoPi)};
      return node_->ack(token);
    }
    case Sub::ResetOdometry:
      odom_ = {};
      return node_->ack(token);
  }
  Driver::on_request(device, req, token);
}

void OdriveCan::shutdown() {
  if (fd_ >= 0) {
    for (Axis& a : axes_) {
      send(cansimple::set_input_vel_frame(a.node_id, {0, 0}));
      send(estop_on_shutdown_ ? cansimple::empty_frame(a.node_id, Cmd::Estop)
                              : cansimple::set_axis_state_frame(a.node_id, AxisState::Idle));
    }
  }
  for (TimerId* t : {&tick_timer_, &power_timer_, &reopen_timer_}) {
    if (*t) node_->loop().cancel_timer(*t);
    *t = 0;
  }
  if (fd_ >= 0) {
    node_->loop().unwatch(fd_);
    if (own_fd_) close(fd_);
    fd_ = -1;
  }
}

void OdriveCan::warn_limited(const char* fmt, ...) {
  uint64_t now = node_->loop().now_us();
  if (last_warn_us_ != 0 && now - last_warn_us_ < 1000000) {
    suppressed_warnings_++;
    return;
  }
  last_warn_us_ = now;
  char text[224];
  va_list args;
  va_start(args, fmt);
  vsnprintf(text, sizeof text, fmt, args);
  va_end(args);
  if (suppressed_warnings_ > 0) {
    log_warn("%s (and %u more warnings in the last second)", text, suppressed_warnings_);
  } else {
    log_warn("%s", text);
  }
  suppressed_warnings_ = 0;
}

extern const DriverEntry kEntry;
const DriverEntry kEntry{"odrive_can", []() -> Driver* { return new OdriveCan; }};

}  // namespace troupe::drivers::odrive_can
