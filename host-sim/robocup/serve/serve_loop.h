// Runs a RoboCup Simulation and serves it (RobocupServer) from one thread,
// on the one paced loop (host-sim/sim_control/pacing.h): cycles in real
// time (or a multiple, or as fast as possible) between polls of the
// network, paused and stepped through simulation:0. troupe-sim runs a
// RoboCup world with it.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "host-sim/robocup/serve/robocup_server.h"
#include "host-sim/sim_control/pacing.h"
#include "runtime/node.h"
#include "runtime/node_secure.h"

namespace troupe::robocup {

struct ServeOptions {
  std::string listen = "localhost";
  /// TCP (and UDP) port; 0: any free port (see ServeLoop::port()).
  uint16_t port = 0;
  /// Multiple of real time; 0: as fast as possible.
  double speed = 1;
  bool paused = false;
  /// Stop after this much simulated time, s (0: run until stopped).
  double seconds = 0;
  /// False: no sockets at all (batch runs); the loop still runs.
  bool serve = true;
  /// Secure sessions; empty: plain TCP.
  SecureSessions secure;
  /// Called before and after every cycle, however it was asked for (the
  /// pace or a client's step): troupe-sim prints the referee's events
  /// after, and serves the robots' Stage sensors around it.
  std::function<void()> before_step, after_step;
  /// Adds drivers of its own to the node, after the RobocupServer and
  /// before the node starts (troupe-sim: the robots' Stage sensors).
  std::function<bool(Node& node, sim::SimControl& control, std::string& error)> add_drivers;
};

class ServeLoop {
 public:
  explicit ServeLoop(Simulation& sim);
  ~ServeLoop();
  ServeLoop(const ServeLoop&) = delete;
  ServeLoop& operator=(const ServeLoop&) = delete;

  /// Opens the server. False with `error` (e.g. the port is taken).
  bool start(const ServeOptions& options, std::string& error);
  /// Runs until request_stop(), the time limit, or the referee's time up.
  void run();
  /// Safe from any thread.
  void request_stop() { stop_ = true; }

  /// The bound TCP port.
  uint16_t port() const;
  Node& node() { return *node_; }
  /// The devices of the game layer (set once start() has added it).
  const RobocupServer& server() const { return *server_; }
  const sim::SimControl& control() const { return control_; }

 private:
  void step(uint32_t n);

  Simulation& sim_;
  ServeOptions options_;
  sim::SimControl control_;
  std::unique_ptr<Node> node_;
  RobocupServer* server_ = nullptr;  // owned by node_
  std::atomic<bool> stop_{false};
  sim::RateMeter rate_;
};

}  // namespace troupe::robocup
