// ODrive "CAN Simple" (firmware 0.5.x): the frames the odrive_can driver and
// the ODrive emulator exchange. Facts from ODrive's odrive-cansimple.dbc:
// an 11-bit id is node_id << 5 | command, payloads are little-endian and
// floats are IEEE-754 binary32. Encoding is explicit byte by byte, so a
// big-endian board (PowerPC) builds the same frames as x86.
#pragma once

#include <linux/can.h>

#include <cstdint>

namespace troupe::cansimple {

/// Highest node id: six bits of the 11-bit id.
inline constexpr uint8_t kMaxNodeId = 0x3F;

/// Command ids (the low five bits of the CAN id).
enum class Cmd : uint8_t {
  Heartbeat = 0x01,             // axis -> host, cyclic (100 ms by default)
  Estop = 0x02,                 // host -> axis, no payload
  GetMotorError = 0x03,         // RTR; reply u64 motor error bits
  GetEncoderError = 0x04,       // RTR; reply u32
  SetAxisState = 0x07,          // u32 requested AxisState
  GetEncoderEstimates = 0x09,   // cyclic (10 ms) or RTR; f32 turns, f32 turns/s
  SetControllerMode = 0x0B,     // i32 ControlMode, i32 InputMode
  SetInputVel = 0x0D,           // f32 turns/s, f32 torque feed-forward N*m
  SetLimits = 0x0F,             // f32 velocity limit turns/s, f32 current limit A
  Reboot = 0x16,                // no payload
  GetBusVoltageCurrent = 0x17,  // RTR; f32 V, f32 A
  ClearErrors = 0x18,           // no payload
  GetControllerError = 0x1D,    // RTR; u32
};

/// Axis states (ODrive's AxisState; the ones the driver and emulator use).
enum class AxisState : uint8_t {
  Undefined = 0,
  Idle = 1,
  StartupSequence = 2,
  FullCalibrationSequence = 3,
  ClosedLoopControl = 8,
};

/// ODrive's ControlMode.
enum class ControlMode : int32_t { Voltage = 0, Torque = 1, Velocity = 2, Position = 3 };
/// ODrive's InputMode (the ones velocity control uses).
enum class InputMode : int32_t { Inactive = 0, Passthrough = 1, VelRamp = 2 };

/// Axis error bits (ODrive's AxisError, firmware 0.5.x).
namespace axis_error {
inline constexpr uint32_t kInvalidState = 0x1;
inline constexpr uint32_t kMotorFailed = 0x40;
inline constexpr uint32_t kSensorlessEstimatorFailed = 0x80;
inline constexpr uint32_t kEncoderFailed = 0x100;
inline constexpr uint32_t kControllerFailed = 0x200;
inline constexpr uint32_t kWatchdogTimerExpired = 0x800;
inline constexpr uint32_t kMinEndstopPressed = 0x1000;
inline constexpr uint32_t kMaxEndstopPressed = 0x2000;
inline constexpr uint32_t kEstopRequested = 0x4000;
inline constexpr uint32_t kOverTemp = 0x40000;
}  // namespace axis_error

/// The name of the lowest set error bit ("WATCHDOG_TIMER_EXPIRED"), for
/// messages; "NONE" for 0, "UNKNOWN" for bits the table lacks.
const char* axis_error_name(uint32_t bits);
const char* axis_state_name(AxisState state);

/// The 11-bit id of a command to or from a node.
constexpr uint32_t make_id(uint8_t node_id, Cmd cmd) {
  return (uint32_t(node_id & kMaxNodeId) << 5) | uint32_t(cmd);
}
constexpr uint8_t node_of(uint32_t can_id) {
  return uint8_t((can_id & CAN_SFF_MASK) >> 5);
}
constexpr uint8_t cmd_of(uint32_t can_id) {
  return uint8_t(can_id & 0x1F);
}

/// What a received frame is, after the checks every reader needs: a
/// standard-id data frame (not extended, not remote, not an error frame).
inline bool is_plain_data(const can_frame& f) {
  return (f.can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_ERR_FLAG)) == 0;
}
/// A Get request: remote frame, or a data frame without payload (ODrive
/// answers both).
inline bool is_get_request(const can_frame& f) {
  if (f.can_id & (CAN_EFF_FLAG | CAN_ERR_FLAG)) return false;
  return (f.can_id & CAN_RTR_FLAG) != 0 || f.len == 0;
}

// ---- Payloads ---------------------------------------------------------------

struct Heartbeat {
  uint32_t axis_error = 0;  // axis_error bits
  AxisState state = AxisState::Undefined;
  bool motor_error = false;       // a motor error is set (Get_Motor_Error tells which)
  bool encoder_error = false;     // an encoder error is set
  bool controller_error = false;  // a controller error is set
  bool trajectory_done = false;
};

struct EncoderEstimates {
  float pos_turns = 0;    // turns since power-up (or within the circular range)
  float vel_turns_s = 0;  // turns/s
};

struct BusVoltageCurrent {
  float volts = 0;  // V
  float amps = 0;   // A, positive when drawing from the supply
};

struct Limits {
  float vel_limit_turns_s = 0;  // turns/s
  float current_limit = 0;      // A
};

struct ControllerModes {
  ControlMode control = ControlMode::Velocity;
  InputMode input = InputMode::Passthrough;
};

struct InputVel {
  float vel_turns_s = 0;  // turns/s
  float torque_ff = 0;    // N*m feed-forward
};

// ---- Building frames ----------------------------------------------------------

can_frame heartbeat_frame(uint8_t node_id, const Heartbeat& hb);
can_frame encoder_estimates_frame(uint8_t node_id, const EncoderEstimates& est);
can_frame bus_voltage_current_frame(uint8_t node_id, const BusVoltageCurrent& bus);
can_frame set_axis_state_frame(uint8_t node_id, AxisState state);
can_frame set_controller_modes_frame(uint8_t node_id, const ControllerModes& modes);
can_frame set_input_vel_frame(uint8_t node_id, const InputVel& in);
can_frame set_limits_frame(uint8_t node_id, const Limits& lim);
/// A command without payload: Estop, Reboot, Clear_Errors (DLC 0).
can_frame empty_frame(uint8_t node_id, Cmd cmd);
/// A Get request: a remote frame (RTR, DLC 0), as ODrive's tools send it.
can_frame get_request_frame(uint8_t node_id, Cmd cmd);
/// A reply carrying one u32 (Get_Encoder_Error, Get_Controller_Error) or one
/// u64 (Get_Motor_Error) in 8 bytes.
can_frame u64_reply_frame(uint8_t node_id, Cmd cmd, uint64_t value);

// ---- Reading frames -----------------------------------------------------------
// Each returns false when the frame is too short for the payload (its DLC
// says fewer bytes than the layout needs); `out` is then unchanged.

bool parse(const can_frame& f, Heartbeat& out);
bool parse(const can_frame& f, EncoderEstimates& out);
bool parse(const can_frame& f, BusVoltageCurrent& out);
bool parse(const can_frame& f, Limits& out);
bool parse(const can_frame& f, ControllerModes& out);
bool parse(const can_frame& f, InputVel& out);
/// Set_Axis_State: the requested state as sent (not checked against AxisState).
bool parse_requested_state(const can_frame& f, uint32_t& state);

// Little-endian field access, independent of the host's byte order.
void put_u32(uint8_t* p, uint32_t v);
uint32_t get_u32(const uint8_t* p);
void put_f32(uint8_t* p, float v);
float get_f32(const uint8_t* p);

}  // namespace troupe::cansimple
