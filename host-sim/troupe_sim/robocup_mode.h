// troupe-sim with a RoboCup world: a Stage world file whose models are a
// robocup_field, a ball, a referee and robocup_robots (host-sim/robocup,
// README "World files") runs as a match on rigid-body physics, served by
// RobocupServer on the same paced loop and the same simulation:0 handler as
// every world (host-sim/sim_control), with the viewer beside it.
#pragma once

#include <memory>
#include <string>

#include "host-sim/robocup/serve/serve_loop.h"
#include "host-sim/troupe_sim/options.h"

namespace troupe::sim {

/// True when the world file holds RoboCup models; false (and the Stage
/// engine loads it, with its own errors) for anything else, unreadable
/// files included.
bool is_robocup_world(const std::string& path);

class RobocupMode {
 public:
  /// Loads the match and opens its server. False with `error`: a bad world
  /// file (file:line), an option a match does not take, a port in use.
  bool init(const SimOptions& options, std::string& error);
  int run();
  void request_stop() { loop_->request_stop(); }
  uint16_t port() const { return loop_->port(); }
  Node& node() { return loop_->node(); }
  robocup::Simulation& simulation() { return *sim_; }

 private:
  std::unique_ptr<robocup::Simulation> sim_;
  std::unique_ptr<robocup::ServeLoop> loop_;
  bool profile_ = false;  // --profile: the cycle's phase table at the end
};

}  // namespace troupe::sim
