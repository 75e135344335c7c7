#include "drivers/odrive_can/cansimple.h"

#include <bit>
#include <cmath>
#include <cstring>

namespace troupe::cansimple {
namespace {

can_frame blank(uint8_t node_id, Cmd cmd, uint8_t len) {
  can_frame f;
  std::memset(&f, 0, sizeof f);
  f.can_id = make_id(node_id, cmd);
  f.len = len;
  return f;
}

void put_i32(uint8_t* p, int32_t v) {
  put_u32(p, uint32_t(v));
}
int32_t get_i32(const uint8_t* p) {
  return int32_t(get_u32(p));
}

}  // namespace

void put_u32(uint8_t* p, uint32_t v) {
  p[0] = uint8_t(v);
  p[1] = uint8_t(v >> 8);
  p[2] = uint8_t(v >> 16);
  p[3] = uint8_t(v >> 24);
}

uint32_t get_u32(const uint8_t* p) {
  return uint32_t(p[0]) | (uint32_t(p[1]) << 8) | (uint32_t(p[2]) << 16) | (uint32_t(p[3]) << 24);
}

void put_f32(uint8_t* p, float v) {
  put_u32(p, std::bit_cast<uint32_t>(v));
}
float get_f32(const uint8_t* p) {
  return std::bit_cast<float>(get_u32(p));
}

const char* axis_error_name(uint32_t bits) {
  if (bits == 0) return "NONE";
  switch (bits & (~bits + 1)) {  // the lowest set bit
    case axis_error::kInvalidState:
      return "INVALID_STATE";
    case axis_error::kMotorFailed:
      return "MOTOR_FAILED";
    case axis_error::kSensorlessEstimatorFailed:
      return "SENSORLESS_ESTIMATOR_FAILED";
    case axis_error::kEncoderFailed:
      return "ENCODER_FAILED";
    case axis_error::kControllerFailed:
      return "CONTROLLER_FAILED";
    case axis_error::kWatchdogTimerExpired:
      return "WATCHDOG_TIMER_EXPIRED";
    case axis_error::kMinEndstopPressed:
      return "MIN_ENDSTOP_PRESSED";
    case axis_error::kMaxEndstopPressed:
      return "MAX_ENDSTOP_PRESSED";
    case axis_error::kEstopRequested:
      return "ESTOP_REQUESTED";
    case axis_error::kOverTemp:
      return "OVER_TEMP";
    default:
      return "UNKNOWN";
  }
}

const char* axis_state_name(AxisState state) {
  switch (state) {
    case AxisState::Undefined:
      return "UNDEFINED";
    case AxisState::Idle:
      return "IDLE";
    case AxisState::StartupSequence:
      return "STARTUP_SEQUENCE";
    case AxisState::FullCalibrationSequence:
      return "FULL_CALIBRATION_SEQUENCE";
    case AxisState::ClosedLoopControl:
      return "CLOSED_LOOP_CONTROL";
  }
  return "OTHER";
}

can_frame heartbeat_frame(uint8_t node_id, const Heartbeat& hb) {
  can_frame f = blank(node_id, Cmd::Heartbeat, 8);
  put_u32(f.data, hb.axis_error);
  f.data[4] = uint8_t(hb.state);
  f.data[5] = hb.motor_error ? 1 : 0;
  f.data[6] = hb.encoder_error ? 1 : 0;
  f.data[7] = uint8_t((hb.controller_error ? 1 : 0) | (hb.trajectory_done ? 0x80 : 0));
  return f;
}

can_frame encoder_estimates_frame(uint8_t node_id, const EncoderEstimates& est) {
  can_frame f = blank(node_id, Cmd::GetEncoderEstimates, 8);
  put_f32(f.data, est.pos_turns);
  put_f32(f.data + 4, est.vel_turns_s);
  return f;
}

can_frame bus_voltage_current_frame(uint8_t node_id, const BusVoltageCurrent& bus) {
  can_frame f = blank(node_id, Cmd::GetBusVoltageCurrent, 8);
  put_f32(f.data, bus.volts);
  put_f32(f.data + 4, bus.amps);
  return f;
}

can_frame set_axis_state_frame(uint8_t node_id, AxisState state) {
  // The state is a u32; the DBC declares the frame 8 bytes long (padding zero).
  can_frame f = blank(node_id, Cmd::SetAxisState, 8);
  put_u32(f.data, uint32_t(state));
  return f;
}

can_frame set_controller_modes_frame(uint8_t node_id, const ControllerModes& modes) {
  can_frame f = blank(node_id, Cmd::SetControllerMode, 8);
  put_i32(f.data, int32_t(modes.control));
  put_i32(f.data + 4, int32_t(modes.input));
  return f;
}

can_frame set_input_vel_frame(uint8_t node_id, const InputVel& in) {
  // The motor must never be told NaN or infinity, whatever computed it: a
  // value that is not a number goes out as 0, a stop.
  auto stop_unless_finite = [](float v) { return std::isfinite(v) ? v : 0.0f; };
  can_frame f = blank(node_id, Cmd::SetInputVel, 8);
  put_f32(f.data, stop_unless_finite(in.vel_turns_s));
  put_f32(f.data + 4, stop_unless_finite(in.torque_ff));
  return f;
}

can_frame set_limits_frame(uint8_t node_id, const Limits& lim) {
  can_frame f = blank(node_id, Cmd::SetLimits, 8);
  put_f32(f.data, lim.vel_limit_turns_s);
  put_f32(f.data + 4, lim.current_limit);
  return f;
}

can_frame empty_frame(uint8_t node_id, Cmd cmd) {
  return blank(node_id, cmd, 0);
}

can_frame get_request_frame(uint8_t node_id, Cmd cmd) {
  can_frame f = blank(node_id, cmd, 0);
  f.can_id |= CAN_RTR_FLAG;
  return f;
}

can_frame u64_reply_frame(uint8_t node_id, Cmd cmd, uint64_t value) {
  can_frame f = blank(node_id, cmd, 8);
  put_u32(f.data, uint32_t(value));
  put_u32(f.data + 4, uint32_t(value >> 32));
  return f;
}

bool parse(const can_frame& f, Heartbeat& out) {
  // Error and state are what matter; flags past a short DLC read as clear.
  if (f.len < 5) return false;
  out.axis_error = get_u32(f.data);
  out.state = AxisState(f.data[4]);
  out.motor_error = f.len > 5 && (f.data[5] & 1);
  out.encoder_error = f.len > 6 && (f.data[6] & 1);
  out.controller_error = f.len > 7 && (f.data[7] & 1);
  out.trajectory_done = f.len > 7 && (f.data[7] & 0x80);
  return true;
}

bool parse(const can_frame& f, EncoderEstimates& out) {
  if (f.len < 8) return false;
  out.pos_turns = get_f32(f.data);
  out.vel_turns_s = get_f32(f.data + 4);
  return true;
}

bool parse(const can_frame& f, BusVoltageCurrent& out) {
  if (f.len < 8) return false;
  out.volts = get_f32(f.data);
  out.amps = get_f32(f.data + 4);
  return true;
}

bool parse(const can_frame& f, Limits& out) {
  if (f.len < 8) return false;
  out.vel_limit_turns_s = get_f32(f.data);
  out.current_limit = get_f32(f.data + 4);
  return true;
}

bool parse(const can_frame& f, ControllerModes& out) {
  if (f.len < 8) return false;
  out.control = ControlMode(get_i32(f.data));
  out.input = InputMode(get_i32(f.data + 4));
  return true;
}

bool parse(const can_frame& f, InputVel& out) {
  // A 4-byte frame sets the velocity alone (no torque feed-forward).
  if (f.len < 4) return false;
  out.vel_turns_s = get_f32(f.data);
  out.torque_ff = f.len >= 8 ? get_f32(f.data + 4) : 0.0f;
  return true;
}

bool parse_requested_state(const can_frame& f, uint32_t& state) {
  if (f.len < 4) return false;
  state = get_u32(f.data);
  return true;
}

}  // namespace troupe::cansimple
