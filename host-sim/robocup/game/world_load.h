// The one loader entry: every world file, a Stage world or a RoboCup match
// (the two are one grammar), is read here, in one pass of the engine's
// loader (host-sim/sim/loader.h). The loader reads the Stage models (walls,
// position robots, sensors, pucks, a ball and kickers in rigid worlds) and
// hands a match's models (robocup_field, referee, ball, robocup_robot, and
// types defined from them) to the game layer's reader (world_spec.h), so
// each keyword has one reader (a match's ball's keys are the engine's
// reader's, sim::load_ball, and its robots' Stage sensors likewise).
//
// A world is a match when it holds a robocup_field, a referee or a
// robocup_robot; its ball then is the match's (the referee watches it).
// Stage models beside a match's are refused, with file:line: the game
// layer does not run Stage robots yet.
#pragma once

#include <optional>
#include <string>

#include "host-sim/robocup/game/world_spec.h"
#include "host-sim/sim/desc.h"
#include "host-sim/world/diagnostics.h"
#include "host-sim/world/worldfile.h"

namespace troupe::robocup {

/// One description of a world: what the engine runs, and the game part.
struct LoadedWorld {
  /// The engine's world; a match's is world_desc(*game).
  sim::WorldDesc desc;
  /// A match's field, ball, referee, robots and physics settings (what
  /// Simulation::create runs); empty for a Stage world.
  std::optional<WorldSpec> game;
};

/// Reads, parses and converts any world file. Warnings and errors go to
/// `diags` with file:line; false when there were errors.
bool load_any_world(const std::string& path, LoadedWorld& out, world::Diagnostics& diags);
/// The same for a parsed file.
bool load_any_world(const world::WorldFile& file, LoadedWorld& out, world::Diagnostics& diags);

}  // namespace troupe::robocup
