// The plugin factory: plugins load from separate shared libraries; every
// failure (missing library, missing symbol, wrong API or kind, bad option)
// is an error naming the plugin and where it was asked for, and the
// simulation runs on without it.
#include <gtest/gtest.h>

#include "sim_fixture.h"

namespace troupe::robocup {
namespace {

bool contains(const std::vector<std::string>& lines, const std::string& what) {
  for (const std::string& l : lines) {
    if (l.find(what) != std::string::npos) return true;
  }
  return false;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

TEST(PluginLoader, LoadsEachKindFromItsOwnLibrary) {
  PluginLoader loader({test::kPluginDir});
  std::string error;
  auto sensor = loader.sensor("camera", error);
  ASSERT_TRUE(sensor) << error;
  auto motion = loader.motion("diff_drive", error);
  ASSERT_TRUE(motion) << error;
  auto player = loader.player("goalkeeper", error);
  ASSERT_TRUE(player) << error;
  Options o("here", "");
  EXPECT_TRUE(motion->configure(o, error)) << error;
}

TEST(PluginLoader, EveryFailureNamesThePlugin) {
  PluginLoader loader({test::kPluginDir, test::kBadPluginDir});
  std::string error;
  EXPECT_FALSE(loader.sensor("kamera", error));
  EXPECT_NE(error.find("sensor plugin 'kamera': not found (no kamera.so in"), std::string::npos) << error;
  EXPECT_NE(error.find("$TROUPE_PLUGIN_PATH adds folders"), std::string::npos) << error;
  EXPECT_FALSE(loader.sensor("no_symbol", error));
  EXPECT_NE(error.find("sensor plugin 'no_symbol': its library has no troupe_plugin_v1"), std::string::npos)
      << error;
  EXPECT_FALSE(loader.sensor("old_api", error));
  EXPECT_NE(error.find("sensor plugin 'old_api': built for plugin ABI v2, this program speaks v1"),
            std::string::npos)
      << error;
  EXPECT_FALSE(loader.sensor("misnamed", error));
  EXPECT_NE(error.find("says it is 'some_other_name'"), std::string::npos) << error;
  EXPECT_FALSE(loader.sensor("goalkeeper", error));
  EXPECT_NE(error.find("sensor plugin 'goalkeeper': it is a player plugin"), std::string::npos) << error;
  EXPECT_FALSE(loader.motion("../plugins/camera", error));
  EXPECT_NE(error.find("a plugin name holds only letters, digits, _ and -"), std::string::npos) << error;
  // Controllers share the folder and the ABI: the kind tells them apart.
  EXPECT_FALSE(loader.player("wander", error));
  EXPECT_NE(error.find("player plugin 'wander': it is a controller plugin"), std::string::npos) << error;
  // An interface of another version is refused too.
  plugin::Loader raw({test::kPluginDir});
  EXPECT_FALSE(raw.make<SensorPlugin>("camera", TROUPE_PLUGIN_SENSOR, kPluginApiVersion + 7, nullptr, error));
  EXPECT_NE(error.find("sensor plugin 'camera': built for sensor interface v2, this program speaks v9"),
            std::string::npos)
      << error;
}

TEST(PluginLoader, OneSearchRule) {
  // The user's folders, the program's ../lib/troupe, $TROUPE_PLUGIN_PATH,
  // the world's folder.
  setenv("TROUPE_PLUGIN_PATH", "/first:/second", 1);
  std::vector<std::string> path = plugin::search_path({"/mine"}, "/worlds");
  unsetenv("TROUPE_PLUGIN_PATH");
  ASSERT_EQ(path.size(), 5u);
  EXPECT_EQ(path[0], "/mine");
  EXPECT_NE(path[1].find("/../lib/troupe"), std::string::npos) << path[1];
  EXPECT_EQ(path[2], "/first");
  EXPECT_EQ(path[3], "/second");
  EXPECT_EQ(path[4], "/worlds");
}

TEST(Simulation, BrokenPluginsAreReportedAndTheRestRuns) {
  std::string error;
  auto sim = test::make_sim(R"(
robocup_robot ( name "ok" team "blue" pose [-1 0 0 0]
  shape ( kind "circle" r 0.2 )
  motion_plugin ( plugin "diff_drive" )
  sensor_plugin ( plugin "odometry" )
)
robocup_robot ( name "broken" team "yellow" pose [1 0 0 0]
  shape ( kind "circle" r 0.2 )
  motion_plugin ( plugin "teleport_drive" )
  sensor_plugin ( plugin "odometry" )
  sensor_plugin ( plugin "camera" fov 9 )
  sensor_plugin ( plugin "laser" bogus 1 )
  sensor_plugin ( plugin "no_symbol" )
  sensor_plugin ( plugin "goalkeeper" )
  sensor_plugin ( plugin "ultrasonic" )
  player ( plugin "striker" aim 3 )
)
)",
                            error);
  ASSERT_TRUE(sim) << error;
  const auto& p = sim->problems();
  EXPECT_EQ(p.size(), 6u) << joined(p);
  EXPECT_TRUE(contains(p, "test.world:9: robot broken: motion plugin 'teleport_drive': not found"))
      << joined(p);
  EXPECT_TRUE(contains(p, "test.world:11: robot broken: sensor plugin 'camera': option 'fov': must be in"))
      << joined(p);
  EXPECT_TRUE(contains(p, "test.world:12: robot broken: sensor plugin 'laser': unknown option 'bogus'"))
      << joined(p);
  EXPECT_TRUE(contains(p, "test.world:13: robot broken: sensor plugin 'no_symbol': its library has no"))
      << joined(p);
  EXPECT_TRUE(contains(p, "test.world:14: robot broken: sensor plugin 'goalkeeper': it is a player plugin"))
      << joined(p);
  EXPECT_TRUE(contains(p, "test.world:16: robot broken: player plugin 'striker': unknown option 'aim'"))
      << joined(p);
  // The rest works: both robots' good sensors measure, the good robot drives.
  sim->command(0, {1, 0, 0});
  sim->command(1, {1, 0, 0});
  sim->run_for(1.0);
  ASSERT_EQ(sim->readings(0).size(), 1u);
  ASSERT_EQ(sim->readings(1).size(), 2u);
  EXPECT_EQ(sim->readings(1)[0].model, "odometry");
  EXPECT_EQ(sim->readings(1)[1].model, "ultrasonic");
  EXPECT_TRUE(sim->readings(1)[1].valid);
  EXPECT_GT(sim->robot(0).pose.x, -0.5) << "the robot with a motion plugin moved";
  EXPECT_NEAR(sim->robot(1).pose.x, 1, 1e-9) << "the one without stands";
  EXPECT_EQ(sim->player_of(1), "");
}

TEST(Simulation, PlayersStartAndStopAtRunTime) {
  std::string error;
  auto sim =
      test::make_sim(test::robot("k", "blue", -4.15, 0, 0,
                                 "  shape ( kind \"circle\" r 0.2 )\n  motion_plugin ( plugin \"omni_drive\" )\n"),
                     error);
  ASSERT_TRUE(sim) << error;
  Options bad("console", "");
  bad.set("policy", "psychic");
  EXPECT_FALSE(sim->start_player("k", "goalkeeper", bad, error));
  EXPECT_NE(error.find("robot k: player plugin 'goalkeeper': option 'policy': expected one of"),
            std::string::npos)
      << error;
  EXPECT_EQ(sim->player_of(0), "");
  Options good("console", "");
  good.set("policy", "pattern");
  good.set("latency", "0");
  ASSERT_TRUE(sim->start_player("k", "goalkeeper", good, error)) << error;
  EXPECT_EQ(sim->player_of(0), "goalkeeper");
  sim->run_for(1.0);
  EXPECT_GT(std::fabs(sim->robot(0).pose.y), 0.1) << "the keeper started its pattern";
  EXPECT_FALSE(sim->start_player("k", "goalkeeper", bad, error));
  EXPECT_EQ(sim->player_of(0), "goalkeeper") << "a failed start leaves the running player alone";
  sim->stop_player("k");
  EXPECT_EQ(sim->player_of(0), "");
  const Pose2 stopped_at = sim->robot(0).pose;
  sim->run_for(1.0);
  EXPECT_NEAR(sim->robot(0).pose.y, stopped_at.y, 0.2) << "without its player the robot comes to rest";
  EXPECT_FALSE(sim->start_player("nobody", "goalkeeper", good, error));
  EXPECT_NE(error.find("no robot named 'nobody'"), std::string::npos);
}

}  // namespace
}  // namespace troupe::robocup
