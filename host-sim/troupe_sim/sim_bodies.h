// What the device emulators see when troupe-sim presents a simulated robot
// as hardware (SITL): the Pioneer's wheels, odometry, stall, sonar and
// battery come from a World robot, and the SICK's scan from its laser. The
// emulators' protocol code is the same as standalone; only their
// surroundings differ (see emulators/p2os/pioneer_world.h and
// emulators/sicklms200/sick_emulator.h).
#pragma once

#include <cstdint>
#include <optional>

#include "host-sim/emulators/p2os/pioneer_world.h"
#include "host-sim/emulators/sicklms200/sick_emulator.h"
#include "host-sim/sim/world.h"

namespace troupe::sim {

/// The robot's sonar ring: its first ranger with more than one transducer.
std::optional<uint32_t> find_sonar_ring(const World& world, RobotId robot);
/// The robot's laser: its first ranger whose single transducer has several
/// samples.
std::optional<uint32_t> find_laser(const World& world, RobotId robot);

/// A Pioneer base that is a simulated robot: wheel speeds become the robot's
/// velocity command, its odometry and stall flag come back, its sonar ring
/// (by transducer order) gives the sonar ranges and its battery the voltage.
class SimPioneerBody final : public emulators::PioneerWorld {
 public:
  /// The robot's sonar ring and first bumper are kept computed from now on.
  SimPioneerBody(World& world, RobotId robot);

  /// Once per world step: the odometry the step reached and the simulated
  /// seconds it took.
  double observe(double waited_s, emulators::PioneerPose& pose) override;
  bool move(double left_mps, double right_mps, double track_m, double dt_s,
            emulators::PioneerPose& pose) override;
  void sense(const emulators::PioneerPose& pose, const drivers::p2os::RobotParams& robot,
             emulators::PioneerSenses& senses) override;

  /// Battery voltage at full and empty charge, V (a Pioneer's 12 V lead-acid).
  static constexpr double kFullV = 13.0, kEmptyV = 11.0;

 private:
  World& world_;
  RobotId robot_;
  std::optional<uint32_t> sonar_;
  std::optional<uint32_t> bumper_;
  // The last command sent (m/s, rad/s) and the pose last handed to the
  // emulator: when the emulator's pose differs, its firmware reset the
  // odometry (SETO, power cycle) and the world's follows.
  double command_v_ = 0, command_w_ = 0;
  bool commanded_ = false;
  std::optional<emulators::PioneerPose> reported_;
  std::optional<double> observed_s_;  // world time at the last step observed, s
};

/// A SICK LMS200 that is a simulated laser: each requested bearing reads
/// the simulated beam nearest to it (the newest scan the world computed);
/// bearings outside the simulated field of view, and beams that hit
/// nothing, read as no return.
class SimLaser final : public emulators::SickWorld {
 public:
  /// `laser`: world-wide ranger index; it is kept computed from now on.
  SimLaser(World& world, uint32_t laser);

  void measure(double first_rad, double step_rad, std::span<float> ranges_m) override;

 private:
  World& world_;
  uint32_t laser_;
};

}  // namespace troupe::sim
