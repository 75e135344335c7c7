// Text commands to a running simulation: what troupe-sim (and its alias
// `troupe robocup`) reads from a script or its standard input with a
// RoboCup world. One command per line, in the file format's syntax:
//
//   run SECONDS            step [N]              reset
//   start ROBOT PLUGIN [key=value ...]           stop ROBOT
//   score                  state                 players          problems
//   ball X Y [VX VY]       place ROBOT X Y A     kick ROBOT
//   command ROBOT VX VY W  quit
#pragma once

#include <functional>
#include <string>

#include "host-sim/robocup/game/simulation.h"
#include "host-sim/robocup/game/statement.h"

namespace troupe::robocup {

class Console {
 public:
  using Printer = std::function<void(const std::string& line)>;

  Console(Simulation& sim, Printer print) : sim_(sim), print_(std::move(print)) {}

  /// Runs one command. False with "where: why" when it is malformed or
  /// fails; the simulation is untouched then. `quit` sets quit().
  bool execute(const Statement& command, std::string& error);
  /// Runs every command of a script; stops at the first error or quit.
  bool execute_script(const std::string& text, const std::string& name, std::string& error);
  bool quit() const { return quit_; }

  /// Steps the simulation, printing referee events as they happen.
  void run_steps(long steps);
  /// Prints the referee's events of the last cycle (for loops that step
  /// the simulation themselves), unless show_events(false).
  void print_events();
  /// False: referee events are not printed (`--quiet`); what a command
  /// was asked for (score, state, ...) still is.
  void show_events(bool on) { show_events_ = on; }

 private:
  Simulation& sim_;
  Printer print_;
  bool quit_ = false;
  bool show_events_ = true;
};

/// "t=12.340 goal yellow (blue 0 : yellow 1)" and the like.
std::string describe(const RefereeEvent& e, const Score& score);

}  // namespace troupe::robocup
