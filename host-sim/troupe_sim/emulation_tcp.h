// troupe-sim --p2os-tcp: MobileSim's (and AMRISim's) way of presenting
// simulated Pioneers. Each robot's base is a Pioneer speaking P2OS on its
// own TCP port (robot i on base + i; MobileSim's first is 8101, where ARIA
// looks before its serial port), one client at a time. The robot's laser,
// when it has one, rides the same connection in MobileSim's SIM packets
// (emulators/p2os/sim_laser_packets.h). So an unchanged ARIA program (or
// 100 of them, for 100 robots) drives troupe-sim's robots.
//
// A client that connects starts a new session (odometry at zero, the
// power-up limits); one that leaves lets the next connect.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "host-sim/emulators/p2os/pioneer_emulator.h"
#include "host-sim/sim/world.h"
#include "host-sim/troupe_sim/sim_bodies.h"

namespace troupe::sim {

class P2osTcp {
 public:
  P2osTcp() = default;
  ~P2osTcp();
  P2osTcp(const P2osTcp&) = delete;
  P2osTcp& operator=(const P2osTcp&) = delete;

  /// Listens for every robot of `world` on `listen`: robot i on
  /// base_port + i (0: a free port each). False with `error` naming the
  /// port that could not be had.
  bool open(World& world, const std::string& listen, int base_port, std::string& error);
  /// Accepts clients and lets every connected robot do what is due by
  /// `now_us` (its own clock, us).
  void step(uint64_t now_us);

  bool empty() const { return robots_.empty(); }
  /// The port serving robot `index` (in world order).
  uint16_t port(size_t index) const { return robots_[index].port; }
  /// One "ROBOT p2os-tcp HOST:PORT" line per robot, each ending in a newline.
  std::string info() const;
  /// Clients connected now.
  size_t clients() const;

 private:
  struct Robot {
    RobotId id = 0;
    std::string name;
    int listen_fd = -1, client_fd = -1;
    uint16_t port = 0;
    std::unique_ptr<SimPioneerBody> body;
    std::unique_ptr<SimLaser> laser;
    std::unique_ptr<emulators::PioneerEmulator> pioneer;
  };
  void accept(Robot& r);
  void drop(Robot& r);

  std::string listen_;
  std::vector<Robot> robots_;
};

}  // namespace troupe::sim
