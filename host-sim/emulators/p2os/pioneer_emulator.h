// A Pioneer robot on a pseudo-terminal, behaving like P2OS/AROS firmware,
// not like any driver:
//  - the handshake: SYNC0, SYNC1, SYNC2 (answered with name, class and
//    subclass), then OPEN. It copes with untidy clients: bytes that do not
//    frame (a modem wake-up "WMS2\r", packets at another baud) are ignored,
//    SYNC0 may be repeated, an out-of-order SYNC starts over silently;
//  - once open, a standard SIP every 100 ms: odometry counters, wheel
//    speeds, battery, stall and bumper bits, and the sonar readings fired
//    since the last SIP (a few per SIP, round the ring);
//  - PULSE, ENABLE, SONAR, VEL, RVEL, VEL2, STOP, SETO, CLOSE; motors move
//    only when enabled, wheel speeds change at a bounded acceleration;
//  - the watchdog: when no packet arrives for ~2 s the motors stop;
//  - a UART's view of baud: when the driver's end of the pty is set to
//    another speed than the robot's, each side hears only garbage.
// Faults (LineFaults) corrupt what it sends; it can vanish and come back.
//
// Time is the caller's: step(now_us) does everything due by `now_us`, so
// a test or troupe-sim drives it from its own loop and clock.
#pragma once

#include <cstdint>
#include <string>

#include "drivers/p2os/p2os_protocol.h"
#include "drivers/p2os/p2os_robot.h"
#include "host-sim/emulators/p2os/pioneer_world.h"
#include "host-sim/emulators/serial_line/line_faults.h"
#include "host-sim/emulators/serial_line/pty_port.h"

namespace troupe::emulators {

class PioneerEmulator {
 public:
  struct Config {
    /// Robot subclass reported in SYNC2; its parameters convert units.
    /// An unknown subclass is reported all the same, with p3dx-sh units.
    std::string model = "p3dx-sh";
    std::string robot_class = "Pioneer";
    std::string name = "Troupe";
    /// The robot's line speed, bit/s.
    uint32_t baud = 9600;
    /// Garble both directions while the driver's end is at another baud.
    bool check_baud = true;
    /// us between SIPs.
    uint64_t sip_period_us = 100'000;
    /// Motors stop when no packet came for this long, us.
    uint64_t watchdog_us = 2'000'000;
    /// Sonar readings per SIP while the sonar fires.
    int sonars_per_sip = 4;
    /// Wheel acceleration, m/s^2.
    double accel = 1.0;
    /// Seed of the fault generator.
    uint64_t seed = 1;
  };

  enum class Session : uint8_t { WaitSync0, WaitSync1, WaitSync2, Ready, Open };

  /// `world` may be null for the default world; it must outlive the emulator.
  explicit PioneerEmulator(Config config, PioneerWorld* world = nullptr);

  /// Creates the pty (see PtyPort::open for `link`).
  bool open(const std::string& link, std::string& error);
  /// What a driver opens.
  const std::string& path() const { return port_.path(); }
  PtyPort& port() { return port_; }

  /// Reads and obeys what arrived, moves the robot, sends what is due.
  void step(uint64_t now_us);

  // ---- Faults ----
  /// Faults on what the robot sends (each packet passes through them).
  LineFaults& faults() { return faults_; }
  /// Faults on what the robot hears (each chunk read passes through them).
  LineFaults& inbound_faults() { return inbound_faults_; }
  /// Sends `bytes` of noise now.
  void inject_noise(size_t bytes);
  /// The port vanishes (pty closed, link removed).
  void vanish();
  /// The port comes back under the same name. The robot kept running
  /// meanwhile: a session left open still streams SIPs.
  bool reappear(std::string& error);
  /// The robot restarts: not synced, motors off, odometry at zero.
  void power_cycle();
  /// The firmware stops talking (true) or resumes (false); it still listens.
  void set_mute(bool mute) { mute_ = mute; }

  // ---- State, for tests and simulators ----
  Session session() const { return session_; }
  bool motors_enabled() const { return motors_enabled_; }
  bool sonar_enabled() const { return sonar_enabled_; }
  bool watchdog_tripped() const { return watchdog_tripped_; }
  /// Wheel speeds now and commanded, m/s.
  double left_mps() const { return left_; }
  double right_mps() const { return right_; }
  double target_left_mps() const { return target_left_; }
  double target_right_mps() const { return target_right_; }
  /// The odometric pose the robot reports (m, m, rad); a simulator may set it.
  const PioneerPose& pose() const { return pose_; }
  void set_pose(const PioneerPose& pose) { pose_ = pose; }
  /// The robot's parameters in use.
  const drivers::p2os::RobotParams& robot() const { return *robot_; }
  uint32_t sips_sent() const { return sips_sent_; }
  uint32_t packets_received() const { return packets_received_; }
  /// The last sensor readings sent (sonar, battery, bumpers).
  const PioneerSenses& senses() const { return senses_; }

 private:
  void receive(std::span<const uint8_t> payload);
  void obey(std::span<const uint8_t> payload);
  void reply(std::span<const uint8_t> payload);
  void send_packet(const drivers::p2os::Packet& packet);
  void send_sip();
  void move(double dt_s);
  void set_wheel_targets(double left_mm_s, double right_mm_s);
  void close_session();
  bool baud_mismatch() const;

  Config config_;
  PioneerWorld default_world_;
  PioneerWorld* world_;
  const drivers::p2os::RobotParams* robot_;
  PtyPort port_;
  std::string link_;
  LineFaults faults_;
  LineFaults inbound_faults_;
  drivers::p2os::PacketScanner scanner_;

  Session session_ = Session::WaitSync0;
  bool motors_enabled_ = false, sonar_enabled_ = false, mute_ = false, watchdog_tripped_ = false;
  double left_ = 0, right_ = 0, target_left_ = 0, target_right_ = 0;  // m/s
  double vel_mm_s_ = 0, rvel_deg_s_ = 0;  // VEL/RVEL targets, combined into wheel targets
  PioneerPose pose_;
  PioneerSenses senses_;
  bool stalled_ = false;
  int next_sonar_ = 0;
  uint64_t now_us_ = 0, last_step_us_ = 0, last_byte_us_ = 0, last_packet_us_ = 0, next_sip_us_ = 0;
  bool started_ = false;
  uint32_t sips_sent_ = 0, packets_received_ = 0;
};

}  // namespace troupe::emulators
