// Loads the controllers a world names (dlopen) and runs them every step.
// A library is found as "<name>.so", "lib<name>.so" or "<name>" (a path)
// in each search directory in turn.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "host-sim/sim/controller.h"
#include "host-sim/world/diagnostics.h"

namespace troupe::sim {

class ControllerHost {
 public:
  struct Options {
    /// Directories searched for controller libraries, in order.
    std::vector<std::string> search_path;
    /// A missing controller leaves its robot idle (a warning) instead of
    /// failing the load (an error).
    bool ignore_missing = false;
  };

  ControllerHost() = default;
  ~ControllerHost();
  ControllerHost(const ControllerHost&) = delete;
  ControllerHost& operator=(const ControllerHost&) = delete;

  /// Creates a controller for every robot whose world-file entry has ctrl.
  /// Errors (missing library or symbol, bad arguments, init refused) name
  /// the controller and the world file line. False when there were errors.
  bool load(World& world, const Options& options, world::Diagnostics& diags);
  /// Attaches a controller made in this process (tests, benchmarks).
  bool attach(World& world, RobotId robot, std::unique_ptr<Controller> controller, std::string& error);
  /// Runs every controller once, in robot order, timed as the world
  /// profile's "controllers" phase.
  void update(World& world);

  /// Messages about controllers that threw or sent a non-finite command
  /// and were stopped since the last call (their robots are told to stop;
  /// the rest run on).
  std::vector<std::string> take_errors();

  size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    RobotId robot;
    std::unique_ptr<Controller> controller;
  };
  void* open_library(const std::string& name, const Options& options, std::string& tried);

  std::vector<Entry> entries_;
  std::vector<void*> libraries_;
  std::vector<std::string> errors_;
  size_t phase_ = SIZE_MAX;
};

}  // namespace troupe::sim
