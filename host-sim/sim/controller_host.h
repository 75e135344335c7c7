// Loads the controllers a world names (plugins of the one plugin loader,
// host-sim/plugin: NAME.so on its search path) and runs them every step.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "host-sim/plugin/plugin_loader.h"
#include "host-sim/sim/controller.h"
#include "host-sim/world/diagnostics.h"

namespace troupe::sim {

class ControllerHost {
 public:
  struct Options {
    /// Folders searched for controller libraries, in order
    /// (plugin::search_path() builds the one rule).
    std::vector<std::string> search_path;
    /// A missing controller leaves its robot idle (a warning) instead of
    /// failing the load (an error).
    bool ignore_missing = false;
  };

  ControllerHost() = default;
  ControllerHost(const ControllerHost&) = delete;
  ControllerHost& operator=(const ControllerHost&) = delete;

  /// Creates a controller for every robot whose world-file entry has ctrl.
  /// Errors (missing library or symbol, bad arguments, init refused) name
  /// the controller and the world file line. False when there were errors.
  bool load(World& world, const Options& options, world::Diagnostics& diags);
  /// Attaches a controller made in this process (tests, benchmarks).
  bool attach(World& world, RobotId robot, std::unique_ptr<Controller> controller, std::string& error);
  /// Attaches a controller a plugin made.
  bool attach(World& world, RobotId robot, plugin::Instance<Controller> controller, std::string& error);
  /// Runs every controller once, in robot order, timed as the world
  /// profile's "controllers" phase.
  void update(World& world);

  /// Messages about controllers that threw and were stopped since the last
  /// call (their robots are told to stop; the rest run on).
  std::vector<std::string> take_errors();

  size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    RobotId robot;
    plugin::Instance<Controller> controller;
  };

  std::vector<Entry> entries_;
  std::vector<std::string> errors_;
  size_t phase_ = SIZE_MAX;
};

}  // namespace troupe::sim
