// Helpers for RoboCup tests: simulations from world text, with the
// project's plugins (and the broken test plugins) on the path.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>

#include "host-sim/robocup/game/simulation.h"
#include "tests/support/build_tree.h"

namespace troupe::robocup::test {

using troupe::testing::kPluginDir;
inline const std::string kBadPluginDir = TROUPE_BINARY_DIR "/tests/robocup/bad_plugins";

/// A world spec from Stage world text (files it names are relative to the
/// examples).
inline bool world_from_text(const std::string& text, WorldSpec& out, std::string& error) {
  return parse_world_text(text, TROUPE_SOURCE_DIR "/examples/robocup/test.world", out, error);
}

inline std::unique_ptr<Simulation> make_sim(const std::string& text, std::string& error) {
  WorldSpec spec;
  if (!world_from_text(text, spec, error)) return nullptr;
  return Simulation::create(std::move(spec), PluginLoader({kPluginDir, kBadPluginDir}), error);
}

/// The inline robot used by many tests: a Pioneer-like box with a kicker.
inline std::string pioneer_block(const std::string& extra = "") {
  return R"(
  mass 20
  shape ( kind "rect" length 0.44 width 0.38 z [0 0.6] )
  kicker ( direction 0 reach 0.03
    state ( name "rest" shape ( kind "rect" x 0.235 length 0.03 width 0.28 z [0.02 0.14] ) )
    state ( name "kick" accel 300 contact 0.02 hold 0.25 next "rest" shape ( kind "rect" x 0.30 length 0.16 width 0.28 z [0.02 0.14] ) )
  )
)" + extra;
}

/// A robot model: `robocup_robot ( name "NAME" team "TEAM" pose [x y 0 a] BODY )`
/// (x, y in m; `a_rad` written in degrees, as Stage poses are).
inline std::string robot(const std::string& name, const std::string& team, double x, double y, double a_rad,
                         const std::string& body) {
  char pose[96];
  std::snprintf(pose, sizeof pose, "pose [%.17g %.17g 0 %.17g]", x, y, a_rad * 180 / kPi);
  return "robocup_robot ( name \"" + name + "\" team \"" + team + "\" " + pose + "\n" + body + ")\n";
}

}  // namespace troupe::robocup::test
