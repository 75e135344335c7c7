#include "host-sim/troupe_sim/robocup_mode.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "host-sim/robocup/game/world_spec.h"
#include "runtime/log.h"

namespace troupe::sim {

const char* robocup_only_option(const SimOptions& options) {
  return !options.script.empty() ? "--script"
         : options.interactive   ? "--interactive"
         : options.quiet         ? "--quiet"
                                 : nullptr;
}

bool RobocupMode::init(const SimOptions& options, robocup::WorldSpec spec, std::string& error) {
  // What belongs to the Stage engine alone.
  const char* refused = !options.emulate.empty()      ? "--emulate"
                        : options.port_per_robot      ? "--port-per-robot"
                        : !options.snapshot.empty()   ? "--snapshot"
                        : !options.log.empty()        ? "--log"
                        : options.ignore_missing_ctrl ? "--ignore-missing-ctrl"
                        : options.no_ctrl             ? "--no-ctrl"
                                                      : nullptr;
  if (refused) {
    error = std::string(refused) + " is for Stage worlds; " + options.world + " is a RoboCup world";
    return false;
  }
  options_ = options;
  if (options.seed_given) spec.seed = options.seed;
  const std::string folder = std::filesystem::path(options.world).parent_path().string();
  robocup::PluginLoader loader(plugin::search_path(options.plugin_path, folder));
  sim_ = robocup::Simulation::create(std::move(spec), std::move(loader), error);
  if (!sim_) return false;
  // A plugin that is missing or refuses its options was reported with its
  // file and line; the match goes on without it.
  if (!sim_->problems().empty())
    log_warn("running without %zu plugin(s), see above", sim_->problems().size());
  // Events and command answers are flushed line by line: a script or a
  // test reading the output sees each as it happens.
  console_ = std::make_unique<robocup::Console>(*sim_, [](const std::string& line) {
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
  });
  console_->show_events(!options.quiet);
  if (options.console()) return true;
  robocup::ServeOptions so;
  so.listen = options.listen;
  so.port = options.port;
  so.speed = options.fast ? 0 : options.speed >= 0 ? options.speed : 1;
  so.paused = options.paused;
  so.seconds = options.quit_time > 0 ? options.quit_time : 0;
  so.serve = options.serve;
  so.secure = options.secure;
  // The robots' Stage sensor models (ranger, camera, fiducial, ...) are the
  // engine's: served by the Stage worlds' own server, limited to them, their
  // indices after the RoboCup sensors' on the same robot. The engine's robot
  // 0 is the ball; robot i + 1 is robot i.
  so.add_drivers = [this](Node& node, SimControl& control, std::string& err) {
    SimServer::Scope scope;
    scope.first_robot = 1;
    scope.sensors_only = true;
    scope.first_index = [this](uint16_t robot, wire::Interface iface) {
      return loop_->server().device_count(robot, iface);
    };
    auto sensors = std::make_unique<SimServer>(sim_->engine(), control, std::move(scope));
    sensors_ = sensors.get();
    return node.add_driver(std::move(sensors), DriverSetup{}, err);
  };
  so.before_step = [this] { sensors_->sync_wanted(); };
  so.after_step = [this] {
    sensors_->publish();
    console_->print_events();
  };
  loop_ = std::make_unique<robocup::ServeLoop>(*sim_);
  return loop_->start(so, error);
}

int RobocupMode::run() {
  const auto wall0 = std::chrono::steady_clock::now();
  const double sim0 = sim_->time_s();
  int status = 0;
  if (loop_) {
    loop_->run();
  } else {
    status = run_console();
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const robocup::Score s = sim_->score();
  std::printf("final: blue %d yellow %d after %.2f s simulated in %.2f s wall (%.1fx real time)\n", s.blue,
              s.yellow, sim_->time_s(), wall, wall > 0 ? (sim_->time_s() - sim0) / wall : 0.0);
  std::fflush(stdout);
  // Where a Stage world prints its step's table (runner.cc), in its format.
  if (options_.profile) std::fprintf(stderr, "%s", sim_->profile_table().c_str());
  return status;
}

// One line at a time, so that `--interactive` answers each as it is typed.
// A script stops at its first bad command; standard input goes on after
// one (the user sees the error and types again). Either way the bad
// command changed nothing and the exit status says so.
int RobocupMode::run_console() {
  const char* program = options_.program.c_str();
  std::ifstream file;
  std::istream* in = &std::cin;
  if (!options_.script.empty()) {
    file.open(options_.script);
    if (!file) {
      std::fprintf(stderr, "%s: %s: cannot open\n", program, options_.script.c_str());
      return 1;
    }
    in = &file;
  }
  const std::string name = options_.script.empty() ? "stdin" : options_.script;
  int status = 0;
  std::string line, error;
  for (int number = 1; !console_->quit() && std::getline(*in, line); ++number) {
    std::vector<robocup::Statement> commands;
    bool ok = robocup::parse_commands(line, name, commands, error, number);
    for (const robocup::Statement& c : commands) {
      if (!ok) break;
      ok = console_->execute(c, error);
    }
    if (!ok) {
      std::fprintf(stderr, "%s: %s\n", program, error.c_str());
      status = 1;
      if (!options_.interactive) break;
    }
  }
  return status;
}

}  // namespace troupe::sim
