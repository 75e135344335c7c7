// One emulated ODrive axis: the firmware's CAN Simple behaviour (axis state
// machine, controller modes, limits, errors, watchdog) and the physics of the
// wheel it turns. No I/O: the bus (odrive_emulator.h) feeds it frames and
// time and sends what it answers.
#pragma once

#include <cstdint>

#include "drivers/odrive_can/cansimple.h"

namespace troupe::emulators::odrive {

struct AxisConfig {
  uint8_t node_id = 0;
  /// Velocity ramp rate in VEL_RAMP input mode, turns/s^2.
  float vel_ramp_rate = 20;
  /// Velocity limit until Set_Limits changes it, turns/s.
  float vel_limit = 10;
  /// Current limit until Set_Limits changes it, A.
  float current_limit = 10;
  /// Time constant of the velocity loop (how fast the wheel follows its
  /// setpoint in closed loop), s.
  float response_time = 0.02f;
  /// Time constant of the unpowered wheel running down by friction, s.
  float coast_time = 0.3f;
  /// Watchdog: with a timeout > 0, an axis that hears no frame for this
  /// long drops to IDLE with WATCHDOG_TIMER_EXPIRED, ms. 0 disables it.
  uint32_t watchdog_timeout_ms = 0;
  /// > 0: positions are reported within [0, wrap_turns) (circular
  /// setpoints); 0: a linear count.
  float wrap_turns = 0;
  /// DC bus voltage with no load, V, and the supply's resistance, ohm.
  float supply_volts = 24;
  float supply_ohms = 0.05f;
  /// Current the axis draws at rest and per turn/s, A and A*s/turn.
  float idle_amps = 0.3f;
  float amps_per_turn_s = 0.15f;
  /// true: a simulator moves the wheel (set_wheel()) and reads the
  /// controller's demand (velocity_demand()); step() then runs the firmware
  /// (ramp, watchdog) but not the wheel's physics.
  bool external_wheel = false;
};

class Axis {
 public:
  explicit Axis(const AxisConfig& config);

  uint8_t node_id() const { return config_.node_id; }

  /// Takes a frame addressed to this axis (node id already matched; RTR and
  /// plain frames). Feeds the watchdog. Writes a reply to `reply` and
  /// returns true when the frame asks for one.
  bool handle(const can_frame& frame, uint64_t now_us, can_frame& reply);

  /// Advances the physics and the watchdog to `now_us`.
  void step(uint64_t now_us);

  can_frame heartbeat() const;
  can_frame encoder_estimates() const;
  /// What the board's supply shows, set by the bus from every axis's draw:
  /// V and A, reported by Get_Bus_Voltage_Current.
  void set_bus(float volts, float amps) {
    bus_volts_ = volts;
    bus_total_amps_ = amps;
  }

  // ---- For a simulator that moves the wheel (AxisConfig::external_wheel) ----

  /// The velocity the controller asks of the motor now, turns/s: the ramped
  /// setpoint while in closed loop, 0 otherwise (the motor is unpowered).
  float velocity_demand() const;
  /// True while the motor is powered (closed loop): an unpowered wheel coasts.
  bool armed() const { return state_ == cansimple::AxisState::ClosedLoopControl; }
  /// The wheel as the simulator moved it: position (unwrapped), turns, and
  /// velocity, turns/s. The encoder estimates report these.
  void set_wheel(double pos_turns, float vel_turns_s) {
    pos_turns_ = pos_turns;
    vel_ = vel_turns_s;
  }

  // ---- Faults ----------------------------------------------------------------

  /// Sets axis error bits and disarms, as a failing motor or encoder does.
  /// `persistent`: the cause stays, so Clear_Errors brings the error back
  /// until clear_fault().
  void inject_error(uint32_t axis_error_bits, bool persistent);
  void clear_fault() { persistent_error_ = 0; }
  /// Power cycle: IDLE, no errors, position back to 0, limits and modes to
  /// their configured defaults.
  void reboot(uint64_t now_us);

  // ---- Observing ---------------------------------------------------------------

  cansimple::AxisState state() const { return state_; }
  uint32_t error() const { return error_; }
  double position_turns() const { return pos_turns_; }  // unwrapped, turns
  float velocity() const { return vel_; }               // turns/s
  float input_vel() const { return input_vel_; }        // turns/s, as last commanded
  float vel_limit() const { return vel_limit_; }        // turns/s
  cansimple::ControlMode control_mode() const { return control_mode_; }
  cansimple::InputMode input_mode() const { return input_mode_; }
  /// Current this axis draws from the bus now, A.
  float bus_amps() const;
  uint32_t watchdog_expiries() const { return watchdog_expiries_; }
  uint32_t malformed_frames() const { return malformed_; }

 private:
  void disarm(uint32_t error_bits);
  void request_state(uint32_t requested);

  AxisConfig config_;
  cansimple::AxisState state_ = cansimple::AxisState::Idle;
  uint32_t error_ = 0;
  uint32_t persistent_error_ = 0;
  bool motor_error_ = false;
  cansimple::ControlMode control_mode_ = cansimple::ControlMode::Velocity;
  cansimple::InputMode input_mode_ = cansimple::InputMode::Passthrough;
  float input_vel_ = 0;      // turns/s
  float vel_setpoint_ = 0;   // turns/s, after the ramp
  float vel_limit_ = 0;      // turns/s
  float current_limit_ = 0;  // A
  float vel_ = 0;            // turns/s
  float accel_ = 0;          // turns/s^2, last step
  double pos_turns_ = 0;
  float bus_volts_ = 0, bus_total_amps_ = 0;  // V, A
  uint64_t last_step_us_ = 0;
  uint64_t last_fed_us_ = 0;
  uint32_t watchdog_expiries_ = 0;
  uint32_t malformed_ = 0;
};

}  // namespace troupe::emulators::odrive
