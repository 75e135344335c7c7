// The SITL rig the tests share: troupe-sim presenting robot r0 of
// examples/worlds/sitl_room.world as a Pioneer (P2OS) and a SICK LMS200 on
// pseudo-terminals, a node config whose p2os and sicklms200 drivers open
// them, and the scenario a client runs against any troupe-node so
// configured (the host's, or the armhf one under qemu-user).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "tests/sitl/child_process.h"

namespace troupe::sitl {

/// troupe-sim with r0 emulated, as a child process.
struct SimRig {
  /// Starts it and waits for its port and the devices' paths (with
  /// `links`: the stable names it makes in `dir`). False with `error`
  /// (including its output) when it does not come up.
  bool start(const std::string& dir, std::string& error, bool links = false);

  ChildProcess sim;
  uint16_t port = 0;
  std::string p2os_path, sick_path;
};

/// The node config (JSON) of a Pioneer with its laser on the rig's ports.
std::string node_config_json(const SimRig& rig);

/// The scenario, with gtest assertions: a client of the node at `node_port`
/// drives the robot forward, then turns it; its odometry follows the ground
/// truth troupe-sim reports on `sim_port`, and its laser (ranger:1) and
/// sonar (ranger:0) read the distances to the room's walls from the true
/// pose. `logs` gives the processes' output for failure messages.
void drive_simulated_pioneer(uint16_t node_port, uint16_t sim_port, const std::function<std::string()>& logs);

}  // namespace troupe::sitl
