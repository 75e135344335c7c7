// The kidnapped robot in troupe-sim, with real processes: troupe-sim runs
// examples/worlds/office.world paused; troupe-node runs the desktop peer
// (boards/desktop/nodes/desktop.json: passthrough -> mapfile -> mcl). The
// test steps the simulation one step at a time through simulation:0 and
// waits for mcl's estimate of that step, so everything is counted in
// simulated steps, whatever the machine's load. Mid-run the robot is
// teleported to another room; mcl must say it is lost and find the robot
// again within a bounded number of steps.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <string>

#include "tests/support/child_process.h"
#include "wire/client/proxies.h"

namespace troupe::testing {
namespace {

using client::Client;

const std::string kSource = TROUPE_SOURCE_DIR;
const std::string kBin = TROUPE_BINARY_DIR;
// Guards a hang only (one step's round trip through both processes).
constexpr double kStepGuardS = 30;
// Tracking: an estimate this close to the truth, m.
constexpr double kOnTrackM = 0.25;
// Recovered: on track for this many consecutive steps (3 s).
constexpr size_t kSettledSteps = 30;
// The bounds the test holds mcl to, in simulated 100 ms steps (measured:
// lost said 3 steps after the teleport, on track again from step 15).
constexpr size_t kNoticeWithinSteps = 30;
constexpr size_t kRecoverWithinSteps = 600;

void replace_all(std::string& s, const std::string& from, const std::string& to) {
  for (size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
}

class MclKidnapSim : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = make_temp_dir("troupe-kidnap-");
    ASSERT_FALSE(dir_.empty());
  }
  void TearDown() override {
    sim_.stop();
    desktop_.stop();
    if (HasFailure()) {
      for (const char* log : {"sim.log", "desktop.log"})
        std::fprintf(stderr, "---- %s\n%s", log, read_text(dir_ + "/" + log).c_str());
    }
    remove_tree(dir_);
  }

  std::string dir_;
  ChildProcess sim_, desktop_;
  uint16_t sim_port_ = free_port();
  uint16_t desktop_port_ = free_port();
};

TEST_F(MclKidnapSim, TeleportedRobotIsFoundAgainWithinBoundedSteps) {
  std::string error;
  ASSERT_TRUE(sim_.start_logged({kBin + "/bin/troupe-sim", kSource + "/examples/worlds/office.world", "--port",
                                 std::to_string(sim_port_), "--seed", "1", "--paused", "--ctrl-path",
                                 kBin + "/controllers"},
                                dir_ + "/sim.log", error))
      << error;
  ASSERT_TRUE(wait_for_listener(sim_port_, 60)) << read_text(dir_ + "/sim.log");
  std::string json = read_text(kSource + "/boards/desktop/nodes/desktop.json");
  ASSERT_FALSE(json.empty());
  replace_all(json, "\"port\": 7000", "\"port\": " + std::to_string(sim_port_));
  replace_all(json, "\"examples/", "\"" + kSource + "/examples/");
  std::ofstream(dir_ + "/desktop.json") << json;
  ASSERT_TRUE(desktop_.start_logged({kBin + "/bin/troupe-node", dir_ + "/desktop.json", "--port",
                                     std::to_string(desktop_port_)},
                                    dir_ + "/desktop.log", error))
      << error;
  ASSERT_TRUE(wait_for_listener(desktop_port_, 60)) << read_text(dir_ + "/desktop.log");

  Client desk("127.0.0.1", desktop_port_);
  ASSERT_TRUE(desk.connect(10000)) << desk.error();
  client::Position2dProxy estimate(desk, 1);
  client::LocalizeProxy localize(desk, 0);
  ASSERT_TRUE(estimate.is_open() && localize.is_open()) << desk.error();
  Client sim("127.0.0.1", sim_port_);
  ASSERT_TRUE(sim.connect(10000)) << sim.error();
  client::SimulationProxy simulation(sim, 0);

  // One simulated step, then mcl's estimate of it (stamped with the step's
  // simulated time) and the truth. False when the estimate never came.
  // mcl publishes localize before position2d: both are in when the
  // estimate is.
  struct Step {
    double error_m;
    bool lost;
  };
  auto step = [&](Step& out) {
    if (!simulation.step(1)) return false;
    const uint64_t t = simulation.sim_time_us();
    auto guard = std::chrono::steady_clock::now() + std::chrono::duration<double>(kStepGuardS);
    while (estimate.time_us() < t) {
      if (std::chrono::steady_clock::now() > guard) return false;
      desk.spin_once(5);
    }
    client::Pose2 truth;
    if (estimate.time_us() != t || !simulation.get_pose("r0", truth)) return false;
    out = {std::hypot(estimate.x() - truth.x, estimate.y() - truth.y), localize.lost()};
    return true;
  };
  // The desktop's passthrough connects to the simulator by itself.
  auto connected = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  Step s{};
  while (!step(s)) ASSERT_LT(std::chrono::steady_clock::now(), connected) << "no estimate from the desktop";

  // 20 s of wandering: tracked, never said lost.
  size_t lost_while_tracking = 0;
  double worst = 0;
  for (int i = 0; i < 200; ++i) {
    ASSERT_TRUE(step(s)) << "step " << i << ": " << desk.error() << sim.error();
    lost_while_tracking += s.lost;
    worst = std::max(worst, s.error_m);
  }
  EXPECT_EQ(lost_while_tracking, 0u);
  EXPECT_LT(worst, kOnTrackM) << "tracking before the kidnapping";

  // Carried off to the top middle room; the wheels saw nothing.
  ASSERT_TRUE(simulation.set_pose("r0", {0.5f, 5.0f, 0.0f})) << sim.error();
  size_t noticed = SIZE_MAX, on_track_since = SIZE_MAX, n = 0;
  bool thrown_off = false;
  for (; n < kRecoverWithinSteps + kSettledSteps; ++n) {
    ASSERT_TRUE(step(s)) << "step " << n << " after the kidnapping";
    thrown_off = thrown_off || s.error_m > 1.0;
    if (s.lost && noticed == SIZE_MAX) noticed = n;
    if (s.error_m >= kOnTrackM || s.lost) {
      on_track_since = SIZE_MAX;
    } else if (on_track_since == SIZE_MAX) {
      on_track_since = n;
    }
    if (on_track_since != SIZE_MAX && n + 1 - on_track_since >= kSettledSteps) break;
  }
  std::printf("kidnapped: said lost after %zu steps, on track again after %zu steps (100 ms each)\n", noticed,
              on_track_since);
  EXPECT_TRUE(thrown_off) << "the teleport did not throw the estimate off";
  EXPECT_LT(noticed, kNoticeWithinSteps) << "mcl never said it was lost";
  ASSERT_NE(on_track_since, SIZE_MAX) << "not recovered within " << kRecoverWithinSteps << " steps";
  EXPECT_LT(on_track_since, kRecoverWithinSteps);
  EXPECT_NE(read_text(dir_ + "/desktop.log").find("lost"), std::string::npos);
}

}  // namespace
}  // namespace troupe::testing
