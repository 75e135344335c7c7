// In-process controllers: loaded from the world file's ctrl names (dlopen),
// missing ones reported by name, broken ones stopped without stopping the
// rest; the example controllers do what they say.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "host-sim/sim/controller_host.h"
#include "tests/sim/scenes.h"
#include "tests/sim/temp_dir.h"
#include "tests/support/build_tree.h"

namespace troupe::sim {
namespace {

ControllerHost::Options options(bool ignore_missing = false) {
  ControllerHost::Options o;
  o.search_path = {testing::kPluginDir};
  o.ignore_missing = ignore_missing;
  return o;
}

std::unique_ptr<World> load(troupe::test::TempDir& dir, const std::string& text, world::Diagnostics& d) {
  return World::load(dir.write("c.world", text), 9, d);
}

const char* kArena = R"(
resolution 0.02
define side block ( points 4 z [0 1] )
model ( name "walls" size [8 8] color "gray30"
  side ( point[0] [0 0] point[1] [8 0] point[2] [8 0.1] point[3] [0 0.1] )
  side ( point[0] [0 7.9] point[1] [8 7.9] point[2] [8 8] point[3] [0 8] )
  side ( point[0] [0 0] point[1] [0.1 0] point[2] [0.1 8] point[3] [0 8] )
  side ( point[0] [7.9 0] point[1] [8 0] point[2] [8 8] point[3] [7.9 8] ) )
define bot position ( size [0.3 0.3] fiducial_return 1
  ranger ( sensor ( range [0 3] fov 270 samples 28 ) )
  fiducial ( range_max 10 fov 360 ) )
)";

TEST(Controllers, WanderExploresWithoutGettingStuck) {
  troupe::test::TempDir dir;
  world::Diagnostics d;
  auto w =
      load(dir, std::string(kArena) + "bot ( name \"a\" pose [-2 -2 0 30] ctrl \"wander speed=0.5\" )\n", d);
  ASSERT_TRUE(w) << d.str();
  ControllerHost host;
  ASSERT_TRUE(host.load(*w, options(), d)) << d.str();
  ASSERT_EQ(host.size(), 1u);
  double travelled = 0, minx = 9, maxx = -9, miny = 9, maxy = -9;
  int stalled = 0;
  Pose last = w->state(0).pose;
  for (int s = 0; s < 1500; ++s) {
    host.update(*w);
    w->step();
    const Pose& p = w->state(0).pose;
    travelled += std::hypot(p.x - last.x, p.y - last.y);
    last = p;
    stalled += w->state(0).stalled;
    minx = std::min(minx, p.x), maxx = std::max(maxx, p.x), miny = std::min(miny, p.y),
    maxy = std::max(maxy, p.y);
  }
  EXPECT_GT(travelled, 30.0);   // 150 s at up to 0.5 m/s
  EXPECT_LT(stalled, 15);       // it avoids the walls rather than hits them
  EXPECT_GT(maxx - minx, 3.0);  // and goes places
  EXPECT_GT(maxy - miny, 3.0);
  EXPECT_TRUE(host.take_errors().empty());
}

double mean_pair_distance(const World& w) {
  double sum = 0;
  int n = 0;
  for (RobotId i = 0; i < w.robot_count(); ++i) {
    for (RobotId j = i + 1; j < w.robot_count(); ++j) {
      sum += std::hypot(w.state(i).pose.x - w.state(j).pose.x, w.state(i).pose.y - w.state(j).pose.y);
      ++n;
    }
  }
  return sum / n;
}

TEST(Controllers, SwarmAggregatesAndDisperses) {
  for (const char* mode : {"aggregate", "disperse"}) {
    troupe::test::TempDir dir;
    std::string text = kArena;
    for (int i = 0; i < 8; ++i) {
      // Aggregators start spread out, dispersers bunched up.
      const double spread = std::string(mode) == "aggregate" ? 2.5 : 0.7;
      text += "bot ( name \"b" + std::to_string(i) + "\" pose [" +
              std::to_string(spread * std::cos(i * 0.785)) + " " +
              std::to_string(spread * std::sin(i * 0.785)) + " 0 " + std::to_string(i * 45) +
              "] ctrl \"swarm " + mode + " spacing=1.2\" )\n";
    }
    world::Diagnostics d;
    auto w = load(dir, text, d);
    ASSERT_TRUE(w) << d.str();
    ControllerHost host;
    ASSERT_TRUE(host.load(*w, options(), d)) << d.str();
    const double before = mean_pair_distance(*w);
    for (int s = 0; s < 600; ++s) {
      host.update(*w);
      w->step();
    }
    const double after = mean_pair_distance(*w);
    if (std::string(mode) == "aggregate") {
      EXPECT_LT(after, 0.75 * before) << mode;
    } else {
      EXPECT_GT(after, 1.5 * before) << mode;
    }
  }
}

TEST(Controllers, MissingControllerIsAnErrorNamingIt) {
  troupe::test::TempDir dir;
  world::Diagnostics d;
  auto w = load(dir, std::string(kArena) + "\nbot ( name \"lost\" ctrl \"no_such_brain fast\" )\n", d);
  ASSERT_TRUE(w) << d.str();
  ControllerHost host;
  EXPECT_FALSE(host.load(*w, options(), d));
  ASSERT_TRUE(d.has_errors());
  const world::Diagnostic& e = d.items().back();
  EXPECT_NE(e.message.find("controller plugin 'no_such_brain': not found"), std::string::npos) << e.str();
  EXPECT_NE(e.message.find("'lost'"), std::string::npos);
  EXPECT_NE(e.message.find("--ignore-missing-ctrl"), std::string::npos);
  EXPECT_EQ(e.loc.line, 13);

  world::Diagnostics d2;
  ControllerHost lenient;
  EXPECT_TRUE(lenient.load(*w, options(true), d2));
  EXPECT_FALSE(d2.has_errors());
  EXPECT_TRUE(d2.contains("stays idle"));
  EXPECT_EQ(lenient.size(), 0u);
}

TEST(Controllers, BadArgumentsAndUnsuitableRobotsAreErrors) {
  troupe::test::TempDir dir;
  world::Diagnostics d;
  auto w = load(
      dir, std::string(kArena) + "bot ( ctrl \"wander speed=fast\" )\nposition ( ctrl \"wander\" )\n", d);
  ASSERT_TRUE(w) << d.str();
  ControllerHost host;
  EXPECT_FALSE(host.load(*w, options(), d));
  EXPECT_TRUE(d.contains("refused its arguments \"speed=fast\"")) << d.str();
  EXPECT_TRUE(d.contains("wander needs a ranger")) << d.str();
}

class Throws final : public Controller {
 public:
  bool init(RobotHandle&, std::string&) override { return true; }
  void update(RobotHandle& robot) override {
    robot.command(Command::velocity(1, 0, 0));
    if (robot.time() >= 1.0) throw std::runtime_error("lost my marbles");
  }
};

class Drives final : public Controller {
 public:
  bool init(RobotHandle&, std::string&) override { return true; }
  void update(RobotHandle& robot) override { robot.command(Command::velocity(0.2, 0, 0)); }
};

// A broken controller on robot "bad" (at the origin) beside Drives on
// robot "good" (3 m away), run for 3 s.
class BrokenController : public ::testing::Test {
 protected:
  // The host's errors after the run.
  std::vector<std::string> run(std::unique_ptr<Controller> broken) {
    WorldDesc desc = test::room(10, 10);
    desc.robots = {test::robot("bad", {0, 0, 0}), test::robot("good", {0, 3, 0})};
    w_ = std::make_unique<World>(desc, Random(1));
    ControllerHost host;
    std::string err;
    EXPECT_TRUE(host.attach(*w_, 0, std::move(broken), err));
    EXPECT_TRUE(host.attach(*w_, 1, std::make_unique<Drives>(), err));
    for (int s = 0; s < 30; ++s) {
      host.update(*w_);
      w_->step();
    }
    return host.take_errors();
  }
  std::unique_ptr<World> w_;
};

TEST_F(BrokenController, AThrowingControllerStopsOnlyItsRobot) {
  const auto errors = run(std::make_unique<Throws>());
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("lost my marbles"), std::string::npos);
  EXPECT_NE(errors[0].find("'bad'"), std::string::npos);
  EXPECT_EQ(w_->state(0).velocity.x, 0);
  EXPECT_NEAR(w_->state(1).pose.x, 0.6, 1e-9);
}

// A controller whose arithmetic went wrong: it drives, then divides by zero.
class GoesNonFinite final : public Controller {
 public:
  bool init(RobotHandle&, std::string&) override { return true; }
  void update(RobotHandle& robot) override {
    const double v = robot.time() < 0.5 ? 0.3 : 0.0 / zero_;
    robot.command(Command::velocity(v, 0, 0));
  }

 private:
  double zero_ = 0;
};

TEST_F(BrokenController, AControllerCommandingNaNIsStoppedAndTheWorldStaysFinite) {
  const auto errors = run(std::make_unique<GoesNonFinite>());
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("'bad'"), std::string::npos) << errors[0];
  EXPECT_NE(errors[0].find("non-finite command ("), std::string::npos) << errors[0];
  EXPECT_NE(errors[0].find("nan, 0, 0) refused"), std::string::npos) << errors[0];
  EXPECT_EQ(w_->state(0).velocity.x, 0);
  EXPECT_TRUE(finite_pose(w_->state(0).pose));
  EXPECT_NEAR(w_->state(0).pose.x, 0.15, 1e-9);  // 5 steps at 0.3 m/s
  EXPECT_NEAR(w_->state(1).pose.x, 0.6, 1e-9);
}

// What a controller remembers is the World's (controller memory), so a
// robot handed to a fresh instance mid-run, as a distributed run hands a
// robot crossing into another process's region, carries on exactly as if
// nothing had happened. Each world is run twice: straight through, and with
// every controller destroyed and loaded anew before step `handover`.
std::vector<Pose> run_with_handover(const std::string& path, int steps, int handover, bool hand_over) {
  world::Diagnostics d;
  auto w = World::load(path, 5, d);
  EXPECT_TRUE(w) << d.str();
  if (!w) return {};
  auto host = std::make_unique<ControllerHost>();
  EXPECT_TRUE(host->load(*w, options(), d)) << d.str();
  for (int s = 0; s < steps; ++s) {
    if (hand_over && s == handover) {
      host = std::make_unique<ControllerHost>();
      EXPECT_TRUE(host->load(*w, options(), d)) << d.str();
    }
    host->update(*w);
    w->step();
  }
  std::vector<Pose> poses;
  for (RobotId r = 0; r < w->robot_count(); ++r) poses.push_back(w->state(r).pose);
  return poses;
}

void expect_same_run_with_a_handover(const std::string& path, int steps, int handover) {
  const std::vector<Pose> straight = run_with_handover(path, steps, handover, false);
  const std::vector<Pose> handed = run_with_handover(path, steps, handover, true);
  ASSERT_FALSE(straight.empty());
  ASSERT_EQ(straight.size(), handed.size());
  for (size_t i = 0; i < straight.size(); ++i) {
    EXPECT_EQ(straight[i].x, handed[i].x) << "robot " << i;
    EXPECT_EQ(straight[i].y, handed[i].y) << "robot " << i;
    EXPECT_EQ(straight[i].a, handed[i].a) << "robot " << i;
  }
}

std::string example_world(const char* name) {
  return std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/" + name;
}

TEST(ControllerHandover, WanderInTheOffice) {
  expect_same_run_with_a_handover(example_world("office.world"), 600, 300);
}

TEST(ControllerHandover, ForagingRobotsCarryingPucks) {
  expect_same_run_with_a_handover(example_world("forage.world"), 400, 200);
}

// swarm remembers only how it wanders while it sees nobody: short-sighted
// robots far apart in the arena, so the handover comes mid-wander.
TEST(ControllerHandover, SwarmRobotsWanderingAlone) {
  troupe::test::TempDir dir;
  const std::string path = dir.write("c.world", std::string(kArena) + R"(
define loner position ( size [0.3 0.3] fiducial_return 1
  ranger ( sensor ( range [0 3] fov 270 samples 28 ) )
  fiducial ( range_max 0.8 fov 360 ) ctrl "swarm aggregate" )
loner ( name "a" pose [-2.5 -2.5 0 0] )
loner ( name "b" pose [2.5 2.5 0 180] )
loner ( name "c" pose [2.5 -2.5 0 90] )
)");
  expect_same_run_with_a_handover(path, 300, 137);
}

TEST(ControllerMemory, ZeroAtTheStartAndAfterAResetAndKeptForAFreshInstance) {
  WorldDesc desc = test::room(5, 5);
  desc.robots.push_back(test::robot("r0", {0, 0, 0}));
  World w(desc, Random(1));
  EXPECT_TRUE(w.controller_memory(0).empty());
  w.set_controller_memory_size(0, 24);
  std::span<std::byte> m = w.controller_memory(0);
  ASSERT_EQ(m.size(), 24u);
  EXPECT_EQ(reinterpret_cast<uintptr_t>(m.data()) % alignof(std::max_align_t), 0u);
  for (std::byte b : m) EXPECT_EQ(b, std::byte{0});
  m[5] = std::byte{42};
  w.step();
  EXPECT_EQ(w.controller_memory(0)[5], std::byte{42});
  w.reset();
  EXPECT_EQ(w.controller_memory(0)[5], std::byte{0});
  EXPECT_THROW(w.controller_memory(RobotId(w.robot_count())), std::out_of_range);
}

}  // namespace
}  // namespace troupe::sim
