#include "host-sim/emulators/odrive/odrive_axis.h"

#include <algorithm>
#include <cmath>

namespace troupe::emulators::odrive {

using troupe::cansimple::AxisState;
using troupe::cansimple::Cmd;
namespace axis_error = troupe::cansimple::axis_error;
namespace cs = troupe::cansimple;

Axis::Axis(const AxisConfig& config)
    : config_(config), vel_limit_(config.vel_limit), current_limit_(config.current_limit) {}

void Axis::disarm(uint32_t error_bits) {
  error_ |= error_bits;
  state_ = AxisState::Idle;
  vel_setpoint_ = 0;
}

void Axis::request_state(uint32_t requested) {
  switch (AxisState(requested)) {
    case AxisState::Idle:
      state_ = AxisState::Idle;
      vel_setpoint_ = 0;
      return;
    case AxisState::ClosedLoopControl:
      // The firmware refuses to arm with an error set; the state stays.
      if (error_ != 0) return;
      state_ = AxisState::ClosedLoopControl;
      vel_setpoint_ = vel_;  // bumpless: the ramp starts from the wheel's speed
      return;
    default:
      // Calibration and other sequences are not emulated: an axis that was
      // calibrated at the factory has nothing to do.
      if (requested > 13) disarm(axis_error::kInvalidState);
      return;
  }
}

bool Axis::handle(const can_frame& f, uint64_t now_us, can_frame& reply) {
  last_fed_us_ = now_us;  // any frame feeds the watchdog
  const uint8_t node = config_.node_id;
  const Cmd cmd = Cmd(cs::cmd_of(f.can_id));
  if (cs::is_get_request(f)) {
    switch (cmd) {
      case Cmd::Heartbeat:
        reply = heartbeat();
        return true;
      case Cmd::GetEncoderEstimates:
        reply = encoder_estimates();
        return true;
      case Cmd::GetBusVoltageCurrent:
        reply = cs::bus_voltage_current_frame(node, {bus_volts_, bus_total_amps_});
        return true;
      case Cmd::GetMotorError:
        reply = cs::u64_reply_frame(node, cmd, motor_error_ ? 0x8 /* DRV_FAULT */ : 0);
        return true;
      case Cmd::GetEncoderError:
      case Cmd::GetControllerError:
        reply = cs::u64_reply_frame(node, cmd, 0);
        return true;
      default:
        break;  // not a Get: an action without payload (below) or unknown
    }
  }
  if (f.can_id & CAN_RTR_FLAG) return false;
  switch (cmd) {
    case Cmd::Estop:
      disarm(axis_error::kEstopRequested);
      break;
    case Cmd::Reboot:
      reboot(now_us);
      break;
    case Cmd::ClearErrors:
      error_ = persistent_error_;
      motor_error_ = motor_error_ && persistent_error_ != 0;
      break;
    case Cmd::SetAxisState: {
      uint32_t requested = 0;
      if (!cs::parse_requested_state(f, requested)) return ++malformed_, false;
      request_state(requested);
      break;
    }
    case Cmd::SetControllerMode: {
      cs::ControllerModes modes;
      if (!cs::parse(f, modes)) return ++malformed_, false;
      control_mode_ = modes.control;
      input_mode_ = modes.input;
      break;
    }
    case Cmd::SetInputVel: {
      cs::InputVel in;
      if (!cs::parse(f, in) || !std::isfinite(in.vel_turns_s)) return ++malformed_, false;
      input_vel_ = in.vel_turns_s;
      break;
    }
    case Cmd::SetLimits: {
      cs::Limits lim;
      if (!cs::parse(f, lim) || !(lim.vel_limit_turns_s >= 0) || !(lim.current_limit >= 0)) {
        return ++malformed_, false;
      }
      vel_limit_ = lim.vel_limit_turns_s;
      current_limit_ = lim.current_limit;
      break;
    }
    default:
      break;  // commands the emulator does not implement are ignored, as unknown ids are
  }
  return false;
}

void Axis::step(uint64_t now_us) {
  if (last_step_us_ == 0) {
    last_step_us_ = last_fed_us_ = now_us;
    return;
  }
  const float dt = float(now_us - last_step_us_) * 1e-6f;
  last_step_us_ = now_us;
  if (config_.watchdog_timeout_ms > 0 &&
      now_us - last_fed_us_ > uint64_t(config_.watchdog_timeout_ms) * 1000u &&
      !(error_ & axis_error::kWatchdogTimerExpired)) {
    watchdog_expiries_++;
    disarm(axis_error::kWatchdogTimerExpired);
  }
  const float before = vel_;
  if (state_ == AxisState::ClosedLoopControl) {
    float target = control_mode_ == cs::ControlMode::Velocity ? input_vel_ : 0.0f;
    target = std::clamp(target, -vel_limit_, vel_limit_);
    if (input_mode_ == cs::InputMode::VelRamp) {
      float max_change = config_.vel_ramp_rate * dt;
      vel_setpoint_ += std::clamp(target - vel_setpoint_, -max_change, max_change);
    } else {
      vel_setpoint_ = target;
    }
  }
  if (config_.external_wheel) return;
  if (state_ == AxisState::ClosedLoopControl) {
    vel_ += (vel_setpoint_ - vel_) * (1.0f - std::exp(-dt / config_.response_time));
  } else {
    vel_ *= std::exp(-dt / config_.coast_time);
  }
  accel_ = dt > 0 ? (vel_ - before) / dt : 0;
  pos_turns_ += double(0.5f * (before + vel_)) * double(dt);
}

float Axis::velocity_demand() const {
  return armed() ? vel_setpoint_ : 0.0f;
}

float Axis::bus_amps() const {
  if (state_ != AxisState::ClosedLoopControl) return config_.idle_amps;
  float amps = config_.idle_amps + config_.amps_per_turn_s * std::fabs(vel_) + 0.02f * std::fabs(accel_);
  return std::min(amps, current_limit_ + config_.idle_amps);
}

can_frame Axis::heartbeat() const {
  cs::Heartbeat hb;
  hb.axis_error = error_;
  hb.state = state_;
  hb.motor_error = motor_error_;
  hb.trajectory_done = true;  // no trajectory is ever running in velocity control
  return cs::heartbeat_frame(config_.node_id, hb);
}

can_frame Axis::encoder_estimates() const {
  double pos = pos_turns_;
  if (config_.wrap_turns > 0) {
    pos = std::fmod(pos, double(config_.wrap_turns));
    if (pos < 0) pos += config_.wrap_turns;
  }
  return cs::encoder_estimates_frame(config_.node_id, {float(pos), vel_});
}

void Axis::inject_error(uint32_t bits, bool persistent) {
  if (bits & axis_error::kMotorFailed) motor_error_ = true;
  if (persistent) persistent_error_ |= bits;
  disarm(bits);
}

void Axis::reboot(uint64_t now_us) {
  state_ = AxisState::Idle;
  error_ = persistent_error_;
  motor_error_ = false;
  control_mode_ = cs::ControlMode::Velocity;
  input_mode_ = cs::InputMode::Passthrough;
  input_vel_ = vel_setpoint_ = vel_ = accel_ = 0;
  vel_limit_ = config_.vel_limit;
  current_limit_ = config_.current_limit;
  pos_turns_ = 0;
  last_step_us_ = last_fed_us_ = now_us;
}

}  // namespace troupe::emulators::odrive
