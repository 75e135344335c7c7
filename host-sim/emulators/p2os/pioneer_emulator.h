// A Pioneer robot behaving like P2OS/AROS firmware, not like any driver:
//  - the handshake: SYNC0, SYNC1, SYNC2 (answered with name, class and
//    subclass), then OPEN. It copes with untidy clients: bytes that do not
//    frame (a modem wake-up "WMS2\r", packets at another baud) are ignored,
//    SYNC0 may be repeated, an out-of-order SYNC starts over silently;
//  - once open, a standard SIP every 100 ms: odometry counters, wheel
//    speeds, battery, stall and bumper bits, and the sonar readings fired
//    since the last SIP (a few per SIP, round the ring or in the POLLING
//    order);
//  - every command of the P2OS manual that moves or configures the base:
//    VEL, RVEL, ROTATE, VEL2, MOVE, HEAD, DHEAD, DCHEAD, STOP, ESTOP under
//    the limits SETV, SETRV, SETA, SETRA set (pioneer_motion.h), SETO,
//    ENABLE, SONAR, POLLING, BUMPSTALL, CONFIG (answered with the 0x20
//    configuration packet), HOSTBAUD, PULSE, CLOSE. Any other command is
//    logged once by name and otherwise ignored, as the firmware ignores
//    what it does not know;
//  - the watchdog: when no packet arrives for ~2 s the motors stop;
//  - with a simulated laser attached (MobileSim's SIM extension, on a TCP
//    line), laser readings in 0x60/0x61 packets after each SIP
//    (sim_laser_packets.h).
// The line (pty or TCP), its faults and baud are SerialEmulator's.
#pragma once

#include <bitset>
#include <cstdint>
#include <string>

#include "drivers/p2os/p2os_protocol.h"
#include "drivers/p2os/p2os_robot.h"
#include "host-sim/emulators/p2os/pioneer_motion.h"
#include "host-sim/emulators/p2os/pioneer_world.h"
#include "host-sim/emulators/p2os/sim_laser_packets.h"
#include "host-sim/emulators/serial_line/serial_emulator.h"

namespace troupe::emulators {

class PioneerEmulator final : public SerialEmulator {
 public:
  struct Config {
    /// Robot subclass reported in SYNC2; its parameters convert units.
    /// An unknown subclass is reported all the same, with p3dx-sh units.
    std::string model = "p3dx-sh";
    std::string robot_class = "Pioneer";
    std::string name = "Troupe";
    /// The robot's line speed at power-up, bit/s (HOSTBAUD changes it).
    uint32_t baud = 9600;
    /// Garble both directions while the driver's end is at another baud.
    bool check_baud = true;
    /// us between SIPs.
    uint64_t sip_period_us = 100'000;
    /// Motors stop when no packet came for this long, us.
    uint64_t watchdog_us = 2'000'000;
    /// Sonar readings per SIP while the sonar fires.
    int sonars_per_sip = 4;
    /// Translational acceleration and deceleration at power-up, m/s^2.
    double accel = 1.0;
    /// Rotational acceleration and deceleration at power-up, deg/s^2.
    double rot_accel_deg = 300;
    /// Seed of the fault generator.
    uint64_t seed = 1;
  };

  enum class Session : uint8_t { WaitSync0, WaitSync1, WaitSync2, Ready, Open };

  /// `world` may be null for the default world; it must outlive the emulator.
  explicit PioneerEmulator(Config config, PioneerWorld* world = nullptr);

  /// Reads and obeys what arrived, moves the robot, sends what is due.
  void step(uint64_t now_us) override;
  uint32_t line_baud() const override { return baud_; }

  /// The robot restarts: not synced, motors off, odometry at zero, the
  /// power-up limits and baud.
  void power_cycle();
  /// A simulated laser whose readings ride the connection in MobileSim's
  /// SIM packets once a client enables it (commands 35-38, 230-233, which
  /// a real robot's firmware reads otherwise). Null detaches; it must
  /// outlive the emulator.
  void set_sim_laser(LaserWorld* laser);

  // ---- State, for tests and simulators ----
  Session session() const { return session_; }
  bool motors_enabled() const { return motors_enabled_; }
  bool sonar_enabled() const { return sonar_enabled_; }
  bool watchdog_tripped() const { return watchdog_tripped_; }
  /// Wheel speeds now and commanded, m/s.
  double left_mps() const { return motion_.left(); }
  double right_mps() const { return motion_.right(); }
  double target_left_mps() const { return motion_.target_left(); }
  double target_right_mps() const { return motion_.target_right(); }
  const PioneerMotion& motion() const { return motion_; }
  /// The odometric pose the robot reports (m, m, rad); a simulator may set it.
  const PioneerPose& pose() const { return pose_; }
  void set_pose(const PioneerPose& pose) { pose_ = updated_at_ = pose; }
  /// The robot's parameters in use.
  const drivers::p2os::RobotParams& robot() const { return *robot_; }
  uint32_t sips_sent() const { return sips_sent_; }
  /// Commands heard that the emulator does not model (each logged once).
  uint32_t unmodelled() const { return unmodelled_; }
  /// The last sensor readings sent (sonar, battery, bumpers).
  const PioneerSenses& senses() const { return senses_; }

 private:
  void on_heard(std::span<const uint8_t> bytes) override;
  bool holds_partial() const override { return scanner_.partial(); }
  void on_stale_partial() override;
  void on_reappear() override { scanner_.reset(); }
  void emit(std::span<const uint8_t> bytes) override { write_line(bytes); }

  void receive(std::span<const uint8_t> payload);
  void obey(std::span<const uint8_t> payload);
  void unmodelled(uint8_t command);
  void reply(std::span<const uint8_t> payload);
  void send_packet(const drivers::p2os::Packet& packet);
  void send_sip();
  void send_config();
  void move(double dt_s);
  void reset_odometry();
  void close_session();
  void reset_limits();

  Config config_;
  PioneerWorld default_world_;
  PioneerWorld* world_;
  const drivers::p2os::RobotParams* robot_;
  drivers::p2os::PacketScanner scanner_;
  PioneerMotion motion_;
  SimLaserPackets sim_laser_;

  Session session_ = Session::WaitSync0;
  uint32_t baud_;
  bool motors_enabled_ = false, sonar_enabled_ = false, watchdog_tripped_ = false;
  uint8_t bump_stall_ = 0;  // BUMPSTALL: bit0 front ring, bit1 rear ring stops the robot
  PioneerPose pose_;
  PioneerPose updated_at_;  // pose_ at the last motion update
  double waited_s_ = 0;     // s stepped since the last motion update
  PioneerSenses senses_;
  bool stalled_ = false;
  // The sonar firing order (POLLING), transducer indices; empty: round the ring.
  uint8_t polling_[PioneerSenses::kMaxSonar] = {};
  size_t polling_size_ = 0, next_sonar_ = 0;
  uint64_t now_us_ = 0, last_step_us_ = 0, last_packet_us_ = 0, next_sip_us_ = 0;
  bool started_ = false;
  uint32_t sips_sent_ = 0, unmodelled_ = 0;
  std::bitset<256> unmodelled_logged_;
};

}  // namespace troupe::emulators
