// p2os: a Pioneer 2/3 robot (P2OS/AROS firmware) on a serial port.
//
// Provides (each at most once, any subset): position2d (odometry, wheel
// velocities, stall; Vel commands), ranger (the sonar ring), power (battery
// volts), bumper (front ring bits 0-6, rear ring bits 7-13).
// Requests: position2d Geometry, MotorPower, SetOdometry, ResetOdometry;
// ranger Geometry, GetConfig, Power (sonar on/off).
//
// An explicit state machine, driven by bytes from the port and a 20 Hz tick,
// never blocking the node's loop:
//
//   Closed --open--> Sync0 --[0]--> Sync1 --[1]--> Sync2 --[2,names]--> Running
//     ^                |  no reply: retry, then the next baud              |
//     |                |  any other packet: CLOSE once, then Sync0 again   |
//     +---- port lost or no baud answers: reopen with backoff -------------+
//                                  no SIP for sip_timeout_ms: CLOSE, Sync0 <-+
//
// Running: OPEN, PULSE, SONAR, ENABLE once; then a SIP every 100 ms from the
// robot, and from us the velocity (on each command, and again every pulse_ms
// while it is not zero) or a PULSE, so the robot's watchdog never fires.
#pragma once

#include <cstdint>
#include <string>

#include "drivers/p2os/p2os_odometry.h"
#include "drivers/p2os/p2os_protocol.h"
#include "drivers/p2os/p2os_robot.h"
#include "drivers/serial_port/serial_session.h"
#include "runtime/driver.h"

namespace troupe::drivers::p2os {

class P2os final : public Driver, private serial::SerialSession::Listener {
 public:
  enum class State : uint8_t { Closed, Sync0, Sync1, Sync2, Running };

  P2os();
  bool setup(Node& node, const DriverSetup& setup, std::string& error) override;
  void on_command(DeviceId device, const wire::Message& command) override;
  void on_request(DeviceId device, const wire::Message& request, RequestToken token) override;
  void shutdown() override;

 private:
  // Connection (p2os.cc)
  void on_session_open() override;
  void on_session_bytes(std::span<const uint8_t> bytes) override;
  void on_session_tick(uint64_t now_us) override;
  void on_session_down() override;
  void handle_packet(std::span<const uint8_t> payload);
  void start_baud(size_t index);
  void send_sync();
  void on_sync_timeout();
  void confused(const char* what);
  void identify(std::span<const uint8_t> payload);
  void enter_running();
  void report_down();
  void send(const Packet& packet);

  // Devices (p2os_devices.cc)
  void handle_sip(std::span<const uint8_t> payload);
  void send_velocity();
  void keep_alive();
  void publish_position();
  void publish_sonar();
  void publish_power(const Sip& sip);
  void publish_bumpers(const Sip& sip);
  void request_position(const wire::Message& request, RequestToken token);
  void request_ranger(const wire::Message& request, RequestToken token);

  serial::SerialSession session_;
  PacketScanner scanner_;
  std::string name_ = "p2os";

  // Devices provided (kNoDevice when not).
  DeviceId position_ = kNoDevice, ranger_ = kNoDevice, power_ = kNoDevice, bumper_ = kNoDevice;

  // Options.
  uint32_t bauds_[5] = {};  // to probe, bit/s
  size_t baud_count_ = 0;
  const RobotParams* forced_model_ = nullptr;
  bool sonar_on_ = true, motors_on_ = true, use_vel2_ = true;
  float max_speed_opt_ = 0, max_turn_opt_ = 0;
  uint64_t pulse_us_ = 0, command_timeout_us_ = 0, sync_timeout_us_ = 0, sip_timeout_us_ = 0;
  uint32_t sync_attempts_ = 0;

  // State machine.
  State state_ = State::Closed;
  size_t baud_index_ = 0;
  uint32_t attempts_ = 0;
  bool settling_ = false;  // CLOSE sent after confusion; packets ignored until the deadline

  // The robot.
  const RobotParams* robot_ = nullptr;
  Odometry odometry_;
  float max_speed_ = 0, max_turn_ = 0;  // m/s, rad/s in force
  float target_v_ = 0, target_w_ = 0;   // commanded: m/s, rad/s
  uint64_t last_command_us_ = 0;
  uint64_t last_sip_us_ = 0;
  uint64_t next_keepalive_us_ = 0;
  float vel_v_ = 0, vel_w_ = 0;  // measured: m/s, rad/s
  bool stalled_ = false;
  bool connected_ = false;
  bool reported_down_ = false;  // a stall was published for the lost connection
  uint16_t sonar_mm_[Sip::kMaxSonar] = {};
  uint32_t sonar_seen_ = 0;  // bit i: transducer i has reported since connecting
  uint32_t jumps_rejected_ = 0;
  bool goto_warned_ = false;
};

}  // namespace troupe::drivers::p2os
