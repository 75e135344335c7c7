// odrive_can: a differential base on two ODrive axes over SocketCAN (the
// "CAN Simple" protocol, drivers/odrive_can/cansimple.h).
//
// Provides: position2d (exactly one): odometry from the axes' encoder
// estimates, velocity, stall plus a fault text while the base cannot move;
// power (optional, at most one): the bus voltage.
// Commands: position2d Vel (vx, va). Requests: Geometry, MotorPower,
// SetOdometry, ResetOdometry.
//
// State machine (one tick per 1/rate_hz):
//
//   Connecting --both heartbeats--> Arming --both CLOSED_LOOP--> Running
//        |                            |  ^                          |
//        | no heartbeat               |  | retry (backoff)          | silent axis,
//        v                            v  |                          | axis error
//      Fault <------------------------+--+--------------------------+
//
// Entering Fault stops both axes (velocity 0, IDLE) and reports stall. Fault
// retries once both axes heartbeat again: Arming clears errors, sets
// velocity control and requests CLOSED_LOOP_CONTROL. An ESTOP_REQUESTED
// error is not cleared by itself: a client's MotorPower(on) does that.
// MotorPower(off) holds both axes in IDLE (MotorsOff) until MotorPower(on).
//
// The descriptor is any that carries `struct can_frame` bytes: a PF_CAN raw
// socket the driver opens (kernel filters for its two node ids) or one given
// in the options (tests and troupe-sim use a socketpair).
#pragma once

#include <cstdint>
#include <string>

#include "drivers/odrive_can/cansimple.h"
#include "drivers/odrive_can/diff_drive.h"
#include "runtime/driver.h"

namespace troupe::drivers::odrive_can {

enum class State : uint8_t { Connecting, Arming, Running, MotorsOff, Fault };
const char* state_name(State s);

/// What the driver knows about one axis from its frames.
struct Axis {
  const char* side = "";  // "left" / "right", for messages
  uint8_t node_id = 0;
  bool invert = false;
  // Heartbeat
  uint32_t heartbeats = 0;         // received since start
  uint64_t last_heartbeat_us = 0;  // loop clock
  cansimple::Heartbeat last;
  // Encoder estimates
  PositionTracker tracker;
  double pending_m = 0;   // travel not yet integrated, m (forward positive)
  bool fresh = false;     // a sample arrived since the last integration
  float vel_turns_s = 0;  // latest velocity estimate, turns/s (as reported)
  uint32_t refused_steps = 0;

  bool alive(uint64_t now_us, uint64_t timeout_us) const {
    return heartbeats > 0 && now_us - last_heartbeat_us <= timeout_us;
  }
};

class OdriveCan : public Driver {
 public:
  OdriveCan() = default;
  ~OdriveCan() override;

  bool setup(Node& node, const DriverSetup& setup, std::string& error) override;
  void on_command(DeviceId device, const wire::Message& command) override;
  void on_request(DeviceId device, const wire::Message& request, RequestToken token) override;
  void on_fd(int fd, uint32_t events) override;
  void on_timer(TimerId id) override;
  void shutdown() override;

 private:
  bool read_options(const DriverSetup& setup, std::string& error);
  bool open_bus(std::string& error);
  void lose_bus(const char* what, int err);
  void bus_down();

  // Frames in
  void handle_frame(const can_frame& f);
  void on_heartbeat(Axis& axis, const cansimple::Heartbeat& hb);
  void on_estimates(Axis& axis, const cansimple::EncoderEstimates& est);
  void on_bus_voltage(const cansimple::BusVoltageCurrent& bus);
  // Frames out
  void send(const can_frame& f);
  void send_both_stop(bool idle);
  void send_arming(Axis& axis);

  // State machine
  void tick();
  void enter(State s);
  void fault(const char* fmt, ...) __attribute__((format(printf, 2, 3)));
  bool both_alive(uint64_t now_us) const;
  bool axis_armed(const Axis& axis) const;

  void publish_position();
  void warn_limited(const char* fmt, ...) __attribute__((format(printf, 2, 3)));

  std::string name_;
  DeviceId position_ = kNoDevice;
  DeviceId power_ = kNoDevice;

  // Options, SI
  std::string ifname_;
  int given_fd_ = -1;
  DriveGeometry geometry_;
  float max_speed_ = 0, max_turn_rate_ = 0, max_wheel_turns_s_ = 0, current_limit_ = 0;
  bool velocity_ramp_ = true, estop_on_shutdown_ = false;
  uint64_t period_us_ = 0, heartbeat_timeout_us_ = 0, arm_timeout_us_ = 0;
  uint64_t retry_delay_us_ = 0, retry_max_us_ = 0, command_timeout_us_ = 0, power_period_us_ = 0;
  float length_ = 0, width_ = 0;

  // Bus
  int fd_ = -1;
  bool own_fd_ = false;
  TimerId tick_timer_ = 0, power_timer_ = 0, reopen_timer_ = 0;
  uint64_t reopen_delay_us_ = 0;

  // State
  Axis axes_[2];  // left, right
  State state_ = State::Connecting;
  uint64_t state_since_us_ = 0;
  uint32_t arm_marks_[2] = {0, 0};  // heartbeat counts when arming began
  bool stalled_ = false;            // from a fault until Running again
  bool latched_ = false;            // fault needs MotorPower(on) to clear
  std::string fault_text_;
  uint64_t retry_wait_us_ = 0;
  uint64_t running_since_us_ = 0;

  // Motion
  float target_v_ = 0, target_w_ = 0;  // m/s, rad/s as commanded
  uint64_t last_command_us_ = 0;
  Odometry odom_;
  bool warned_goto_ = false;

  // Rate-limited warnings: at most one line a second, the rest counted.
  uint64_t last_warn_us_ = 0;
  uint32_t suppressed_warnings_ = 0;
};

}  // namespace troupe::drivers::odrive_can
