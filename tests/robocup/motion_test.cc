// Motion plugins: the differential drive's limits, the omni drive's
// holonomy and wheel limits, and the learned model trained from a logged
// run of another motion model.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "host-sim/robocup/game/motion_log.h"
#include "host-sim/robocup/plugins/learned_motion/motion_model.h"
#include "sim_fixture.h"

namespace troupe::robocup {
namespace {

PluginInstance<MotionPlugin> motion(const std::string& name, Options o = {}) {
  PluginLoader loader({test::kPluginDir});
  std::string error;
  auto m = loader.motion(name, error);
  EXPECT_TRUE(m) << error;
  if (m) {
    EXPECT_TRUE(m->configure(o, error)) << error;
  }
  return m;
}

TEST(DiffDrive, AcceleratesWithinItsLimitsAndNeverSlidesSideways) {
  Options o;
  o.set("max_speed", "1.5");
  o.set("accel", "2");
  auto m = motion("diff_drive", o);
  Twist v;
  for (int i = 0; i < 10; ++i) v = m->drive({3, 1, 0}, v, 0.01);
  EXPECT_NEAR(v.vx, 0.2, 1e-12) << "2 m/s^2 for 0.1 s";
  EXPECT_EQ(v.vy, 0) << "a differential drive cannot move sideways";
  for (int i = 0; i < 200; ++i) v = m->drive({3, 0, 0}, v, 0.01);
  EXPECT_NEAR(v.vx, 1.5, 1e-12) << "capped at max_speed";
  EXPECT_EQ(m->drive({0, 0, 0}, {1, 0.7, 0}, 0.01).vy, 0) << "a sideways push is taken out by the wheels";
}

TEST(OmniDrive, MovesInAnyDirectionAndScalesImpossibleCommands) {
  Options o;
  o.set("wheel_speed", "2");
  o.set("wheel_accel", "1000");
  auto m = motion("omni_drive", o);
  Twist v;
  for (int i = 0; i < 5; ++i) v = m->drive({0, 1, 0}, v, 0.01);
  EXPECT_NEAR(v.vx, 0, 1e-9);
  EXPECT_NEAR(v.vy, 1, 1e-9) << "straight sideways";
  for (int i = 0; i < 5; ++i) v = m->drive({10, 10, 0}, v, 0.01);
  EXPECT_NEAR(v.vx, v.vy, 1e-9) << "scaled down as a whole, the direction is kept";
  EXPECT_LT(v.vx, 10);
  Options bad;
  bad.set("angles", "0,0,0");
  PluginLoader loader({test::kPluginDir});
  std::string error;
  auto parallel = loader.motion("omni_drive", error);
  ASSERT_TRUE(parallel);
  EXPECT_FALSE(parallel->configure(bad, error));
  EXPECT_NE(error.find("must not be parallel"), std::string::npos) << error;
}

const char* kDiffDrive = "  motion_plugin ( plugin \"diff_drive\" max_speed 2 accel 2.5 turn_accel 15 )\n";

// A log of the Pioneer's diff drive driven with random commands.
std::string recorded_log(uint64_t seed, double seconds) {
  std::string error;
  auto sim = test::make_sim(
      "referee ( enabled 0 )\n" +
          test::robot("r", "blue", 0, 0, 0, test::pioneer_block(kDiffDrive)),
      error);
  EXPECT_TRUE(sim) << error;
  MotionLogSettings s;
  s.seed = seed;
  s.seconds = seconds;
  std::ostringstream out;
  EXPECT_TRUE(write_motion_log(*sim, 0, s, out, error)) << error;
  return out.str();
}

std::string save(const std::string& name, const std::string& text) {
  const std::string path = TROUPE_BINARY_DIR "/tests/robocup/" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(LearnedMotion, PredictsADiffDriveFarBetterThanHoldingTheVelocity) {
  std::vector<MotionSample> train, test_samples;
  double cycle = 0;
  std::string error;
  ASSERT_TRUE(read_motion_log(save("train.motionlog", recorded_log(1, 90)), train, cycle, error)) << error;
  EXPECT_NEAR(cycle, 0.01, 1e-9);
  ASSERT_TRUE(read_motion_log(save("test.motionlog", recorded_log(2, 30)), test_samples, cycle, error))
      << error;
  MotionModel model;
  ASSERT_TRUE(MotionModel::fit(train, cycle, model, error)) << error;
  // Held-out run: the model against "the velocity stays as it is", as
  // ratios of squared error summed over forward and turn velocity.
  double model_err = 0, hold_err = 0;
  for (const MotionSample& s : test_samples) {
    const Twist p = model.predict(s.velocity, s.command);
    model_err += std::pow(p.vx - s.next.vx, 2) + std::pow(p.w - s.next.w, 2);
    hold_err += std::pow(s.velocity.vx - s.next.vx, 2) + std::pow(s.velocity.w - s.next.w, 2);
  }
  EXPECT_LT(model_err, 0.05 * hold_err);
  // Saved and loaded, it predicts the same.
  const std::string path = TROUPE_BINARY_DIR "/tests/robocup/pioneer.motion";
  ASSERT_TRUE(model.save(path, error)) << error;
  MotionModel loaded;
  ASSERT_TRUE(MotionModel::load(path, loaded, error)) << error;
  const Twist a = model.predict({0.5, 0, 1}, {1.5, 0, -2}), b = loaded.predict({0.5, 0, 1}, {1.5, 0, -2});
  EXPECT_NEAR(a.vx, b.vx, 1e-12);
  EXPECT_NEAR(a.w, b.w, 1e-12);

  // As a plugin it drives a robot along nearly the path the diff drive does.
  std::string world = "referee ( enabled 0 )\nball ( pose [0 -2 0 0] )\n";
  world += test::robot("d", "blue", -2, 0, 0, test::pioneer_block(kDiffDrive));
  world += test::robot("l", "yellow", 2, 0, 0,
                       test::pioneer_block("  motion_plugin ( plugin \"learned_motion\" model \"" + path + "\" )\n"));
  auto sim = test::make_sim(world, error);
  ASSERT_TRUE(sim) << error;
  ASSERT_TRUE(sim->problems().empty()) << sim->problems()[0];
  for (int i = 0; i < 200; ++i) {
    const MotionCommand c{1.2, 0, i < 100 ? 1.5 : -1.0};
    sim->command(0, c);
    sim->command(1, c);
    sim->step();
  }
  const Pose2 d = sim->robot(0).pose, l = sim->robot(1).pose;
  EXPECT_NEAR(l.x - 2, d.x + 2, 0.05);
  EXPECT_NEAR(l.y, d.y, 0.05);
  EXPECT_NEAR(wrap_angle(l.a - d.a), 0, 0.05);
}

TEST(LearnedMotion, BadModelsAndLogsSayWhere) {
  MotionModel m;
  std::string error;
  EXPECT_FALSE(
      MotionModel::load(save("bad1.motion", "troupe-learned-motion 1\ncycle 0.01\nvx 1 2 3\n"), m, error));
  EXPECT_NE(error.find("bad1.motion:3: vx: expected 45 finite weights"), std::string::npos) << error;
  EXPECT_FALSE(MotionModel::load(save("bad2.motion", "# hi\nsomething else\n"), m, error));
  EXPECT_NE(error.find("bad2.motion:2: not a learned motion model"), std::string::npos) << error;
  std::vector<MotionSample> samples;
  double cycle;
  EXPECT_FALSE(read_motion_log(save("bad.motionlog", "0 0 0 0 0 0 0\n0.01 1 2\n"), samples, cycle, error));
  EXPECT_NE(error.find("bad.motionlog:2: expected `time vx vy w cmd_vx cmd_vy cmd_w`"), std::string::npos)
      << error;
  EXPECT_FALSE(MotionModel::fit({}, 0.01, m, error));
  // The plugin names the option when its model file is broken.
  PluginLoader loader({test::kPluginDir});
  auto plugin = loader.motion("learned_motion", error);
  ASSERT_TRUE(plugin);
  Options o("r.robot:4", TROUPE_BINARY_DIR "/tests/robocup");
  o.set("model", "bad1.motion");
  EXPECT_FALSE(plugin->configure(o, error));
  EXPECT_NE(error.find("option 'model': "), std::string::npos) << error;
  EXPECT_NE(error.find("bad1.motion:3"), std::string::npos) << error;
}

}  // namespace
}  // namespace troupe::robocup
