// troupe-sim with a RoboCup world: a Stage world file whose models are a
// robocup_field, a ball, a referee and robocup_robots (host-sim/robocup,
// README "World files") runs as a match on rigid-body physics, served by
// RobocupServer on the same paced loop and the same simulation:0 handler as
// every world (host-sim/sim_control), with the viewer beside it; the
// robots' Stage sensor models (ranger, camera, ...) are served by SimServer,
// as in every Stage world. Or, with
// --script / --interactive, driven by console commands between cycles
// (robocup/game/console.h), flat out and unserved. Either way the referee's
// events go to standard output as they happen, then the final score.
#pragma once

#include <memory>
#include <string>

#include "host-sim/robocup/game/console.h"
#include "host-sim/robocup/serve/serve_loop.h"
#include "host-sim/troupe_sim/options.h"
#include "host-sim/troupe_sim/sim_server.h"

namespace troupe::sim {

/// The first option given that only a RoboCup world takes (the console,
/// --quiet), or null: a Stage world refuses it.
const char* robocup_only_option(const SimOptions& options);

class RobocupMode {
 public:
  /// Builds the match `spec` (the game part of options.world, read by the
  /// one loader: robocup/game/world_load.h) and opens its server (none
  /// with a console). False with `error`: an option a match does not take,
  /// a world the game layer cannot build, a port in use.
  bool init(const SimOptions& options, robocup::WorldSpec spec, std::string& error);
  /// Runs the match to its end, then prints the final line on standard
  /// output. The exit status: 0, or 1 when the console's script cannot be
  /// read or one of its commands failed.
  int run();
  /// Safe from any thread; nothing to stop with a console (it reads its
  /// commands to the end).
  void request_stop() {
    if (loop_) loop_->request_stop();
  }
  /// False with a console: nothing is served, so there is no node, no
  /// port and no viewer.
  bool serving() const { return loop_ != nullptr; }
  uint16_t port() const { return loop_->port(); }
  Node& node() { return loop_->node(); }
  robocup::Simulation& simulation() { return *sim_; }

 private:
  int run_console();

  SimOptions options_;
  std::unique_ptr<robocup::Simulation> sim_;
  std::unique_ptr<robocup::Console> console_;
  std::unique_ptr<robocup::ServeLoop> loop_;
  /// The robots' Stage sensors (owned by the loop's node; none with a
  /// console).
  SimServer* sensors_ = nullptr;
};

}  // namespace troupe::sim
