// The one loader entry (host-sim/robocup/game/world_load.h): every world
// under examples/ (RoboCup matches included) and Stage's simple.world load
// through it; a match's models reach the game layer's reader from inside
// the engine's loader, Stage worlds come out as the engine's loader reads
// them, and what a match cannot hold is refused with file:line.
#include "host-sim/robocup/game/world_load.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "host-sim/sim/loader.h"
#include "host-sim/sim/world.h"
#include "tests/sim/temp_dir.h"

namespace troupe::robocup {
namespace {

std::vector<std::string> example_worlds() {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::recursive_directory_iterator(TROUPE_SOURCE_DIR "/examples")) {
    if (e.is_regular_file() && e.path().extension() == ".world") out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

bool is_match_file(const std::string& path) {
  return path.find("/examples/robocup/") != std::string::npos;
}

TEST(OneLoader, EveryExampleWorldLoadsAndRuns) {
  const std::vector<std::string> worlds = example_worlds();
  // The Stage examples and the two matches, at least.
  ASSERT_GE(worlds.size(), 12u);
  size_t matches = 0;
  for (const std::string& path : worlds) {
    SCOPED_TRACE(path);
    LoadedWorld w;
    world::Diagnostics d;
    ASSERT_TRUE(load_any_world(path, w, d)) << d.str();
    EXPECT_EQ(d.items().size(), 0u) << d.str();
    EXPECT_EQ(w.game.has_value(), is_match_file(path));
    EXPECT_FALSE(w.desc.robots.empty());
    if (w.game) {
      ++matches;
      EXPECT_EQ(w.desc.physics, sim::Physics::Rigid);
      EXPECT_EQ(w.desc.robots[0].name, "ball") << "a match's engine holds its ball first";
      EXPECT_EQ(w.desc.robots.size(), w.game->robots.size() + 1);
    } else {
      // What the engine's loader alone reads.
      sim::WorldDesc alone;
      world::Diagnostics d2;
      ASSERT_TRUE(sim::load_world_file(path, alone, d2)) << d2.str();
      ASSERT_EQ(w.desc.robots.size(), alone.robots.size());
      for (size_t i = 0; i < alone.robots.size(); ++i) EXPECT_EQ(w.desc.robots[i].name, alone.robots[i].name);
      EXPECT_EQ(w.desc.statics.size(), alone.statics.size());
    }
    // The engine builds and steps what came out.
    sim::World engine(w.desc, sim::Random(1));
    engine.step();
    EXPECT_EQ(engine.steps(), 1u);
  }
  EXPECT_EQ(matches, 2u);
}

TEST(OneLoader, StagesSimpleWorldLoads) {
  const std::string simple = std::string(TROUPE_SHARED_DATA) + "/stage/simple.world";
  if (!std::filesystem::exists(simple)) GTEST_SKIP() << "no Stage test data at " << simple;
  LoadedWorld w;
  world::Diagnostics d;
  ASSERT_TRUE(load_any_world(simple, w, d)) << d.str();
  EXPECT_FALSE(w.game.has_value());
  EXPECT_EQ(w.desc.physics, sim::Physics::Kinematic);
  EXPECT_EQ(w.desc.robots.size(), 2u);
  EXPECT_EQ(w.desc.statics.size(), 1u);
}

TEST(OneLoader, AMatchsModelsGoToTheGameLayer) {
  troupe::test::TempDir dir;
  LoadedWorld w;
  world::Diagnostics d;
  ASSERT_TRUE(load_any_world(dir.write("m.world", R"(interval_sim 10
restitution 0.4
robocup_field ( length 9 width 5 )
ball ( radius 0.1 pose [1 0.5 0 0] )
referee ( )
robocup_robot ( name "blue1" team "blue" pose [-4 0 0 0] shape ( kind "circle" r 0.2 ) )
)"),
                             w, d))
      << d.str();
  EXPECT_EQ(d.items().size(), 0u) << d.str();
  ASSERT_TRUE(w.game.has_value());
  EXPECT_DOUBLE_EQ(w.game->physics.restitution, 0.4);
  EXPECT_DOUBLE_EQ(w.game->physics.cycle_s, 0.01);
  EXPECT_DOUBLE_EQ(w.game->ball.radius, 0.1);
  ASSERT_EQ(w.game->robots.size(), 1u);
  EXPECT_EQ(w.game->robots[0].name, "blue1");
  ASSERT_EQ(w.desc.robots.size(), 2u);
  EXPECT_EQ(w.desc.robots[0].name, "ball");
  EXPECT_DOUBLE_EQ(w.desc.robots[0].pose.x, 1);
  EXPECT_EQ(w.desc.robots[1].name, "blue1");
}

TEST(OneLoader, AMatchsMistakeAndAStageModelInAMatchAreErrorsWithFileAndLine) {
  troupe::test::TempDir dir;
  {
    LoadedWorld w;
    world::Diagnostics d;
    EXPECT_FALSE(load_any_world(dir.write("m.world", "robocup_field ( )\nball ( radius 7 )\n"), w, d));
    EXPECT_NE(d.str().find("m.world:2"), std::string::npos) << d.str();
    EXPECT_NE(d.str().find("radius"), std::string::npos) << d.str();
  }
  {
    LoadedWorld w;
    world::Diagnostics d;
    EXPECT_FALSE(load_any_world(dir.write("m.world", "robocup_field ( )\nposition ( name \"r\" )\n"), w, d));
    EXPECT_NE(d.str().find("m.world:2"), std::string::npos) << d.str();
    EXPECT_NE(d.str().find("'position' is no RoboCup model"), std::string::npos) << d.str();
  }
}

TEST(OneLoader, AStageWorldsBallIsTheEnginesNotAMatch) {
  troupe::test::TempDir dir;
  LoadedWorld w;
  world::Diagnostics d;
  ASSERT_TRUE(load_any_world(dir.write("s.world", R"(physics "rigid"
ball ( pose [1 0 0 0] )
position ( name "r" )
)"),
                             w, d))
      << d.str();
  EXPECT_FALSE(w.game.has_value());
  ASSERT_EQ(w.desc.robots.size(), 2u);
  EXPECT_TRUE(w.desc.robots[0].puck);
  EXPECT_EQ(w.desc.robots[1].name, "r");
}

}  // namespace
}  // namespace troupe::robocup
