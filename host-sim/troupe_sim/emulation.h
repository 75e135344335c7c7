// troupe-sim --emulate: simulated robots presented as hardware (SITL). Each
// emulated robot's base becomes a Pioneer speaking P2OS and its laser a
// SICK LMS200, each on a pseudo-terminal, so a real troupe-node with its
// real p2os and sicklms200 drivers (even a cross-built one under qemu-user)
// drives the simulated robot.
//
//   Emulation e;
//   e.add(world, "r0=p2os,sicklms200", error);   // robot by name or number
//   e.open(error);                                // the ptys
//   for (;;) e.step(clock_us);                    // in the simulator's loop
//
// The emulators never block: step() reads what the drivers wrote, answers,
// and sends what is due (a SIP every 100 ms, scans as fast as the line's
// baud allows) by the clock it is given.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "host-sim/emulators/p2os/pioneer_emulator.h"
#include "host-sim/emulators/sicklms200/sick_emulator.h"
#include "host-sim/sim/world.h"
#include "host-sim/troupe_sim/sim_bodies.h"

namespace troupe::sim {

/// A device kind troupe-sim can emulate.
enum class EmulatedKind : uint8_t { P2os, SickLms200 };

/// "p2os", "sicklms200".
const char* emulated_kind_name(EmulatedKind kind);

class Emulation {
 public:
  /// One emulated device, for the info lines.
  struct Device {
    RobotId robot = 0;
    std::string robot_name;
    EmulatedKind kind = EmulatedKind::P2os;
    /// What a driver opens: "/dev/pts/N" (or the link under links_dir).
    std::string path;
  };

  Emulation() = default;
  Emulation(const Emulation&) = delete;
  Emulation& operator=(const Emulation&) = delete;

  /// Adds the devices of one --emulate ROBOT=DEVICE[,DEVICE] spec; ROBOT is
  /// a robot's name or its number. False with `error` naming what is wrong
  /// (unknown robot or device, a robot emulated twice, a laser missing).
  /// The emulated robot's sensors are kept computed from now on.
  bool add(World& world, const std::string& spec, std::string& error);
  /// Opens every device's pseudo-terminal. With a non-empty `links_dir`,
  /// each also gets a stable name there: ROBOT-DEVICE (r0-p2os).
  bool open(const std::string& links_dir, std::string& error);

  /// Lets every emulator do what is due by `now_us` (its own clock, us).
  void step(uint64_t now_us);

  bool empty() const { return robots_.empty(); }
  /// Every device, in the order added (valid after open()).
  std::vector<Device> devices() const;
  /// One "ROBOT DEVICE PATH" line per device, each ending in a newline.
  std::string info() const;

 private:
  struct Robot {
    RobotId id = 0;
    std::string name;
    std::unique_ptr<SimPioneerBody> body;
    std::unique_ptr<emulators::PioneerEmulator> pioneer;
    std::unique_ptr<SimLaser> laser;
    std::unique_ptr<emulators::SickEmulator> sick;
  };

  std::vector<Robot> robots_;
};

}  // namespace troupe::sim
