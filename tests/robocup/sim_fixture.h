// Helpers for RoboCup tests: simulations from world text, with the
// project's plugins (and the broken test plugins) on the path.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "host-sim/robocup/game/simulation.h"

namespace troupe::robocup::test {

inline const std::string kPluginDir = TROUPE_BINARY_DIR "/host-sim/robocup/plugins";
inline const std::string kBadPluginDir = TROUPE_BINARY_DIR "/tests/robocup/bad_plugins";

/// A world spec from text (files it names are relative to the examples).
inline bool world_from_text(const std::string& text, WorldSpec& out, std::string& error) {
  std::vector<Statement> st;
  const std::string name = TROUPE_SOURCE_DIR "/examples/robocup/test.world";
  return parse_config_text(text, name, st, error) && read_world(st, name, out, error);
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
  shape rect length=0.44 width=0.38 z=0,0.6
  kicker direction=0 reach=0.03 {
    state rest { shape rect x=0.235 length=0.03 width=0.28 z=0.02,0.14 }
    state kick accel=300 contact=0.02 hold=0.25 next=rest { shape rect x=0.30 length=0.16 width=0.28 z=0.02,0.14 }
  }
)" + extra;
}

}  // namespace troupe::robocup::test
