#include "tests/sitl/sitl_rig.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <thread>

#include "drivers/p2os/p2os_robot.h"
#include "host-sim/emulators/serial_line/room.h"
#include "wire/client/proxies.h"

namespace troupe::sitl {
namespace {

using client::Client;
using client::Pose2;

// Bounds a wait for something that must happen (hangs, not speed): generous
// for a loaded machine and a node under qemu-user.
constexpr int kWaitMs = 60000;
// sitl_room.world: walls' inner faces at +-2.95 m; the laser 0.16 m ahead of
// the robot's centre, reading at most 8 m; the sonar at most 5 m.
const emulators::Room kRoom{2.95, 2.95};
constexpr double kLaserX = 0.16, kLaserMax = 8.0, kSonarMax = 5.0;
// Ranges agree with the true pose within this, m: the world's 2 cm cells and
// the scanner's 1 cm units.
constexpr double kRangeTolerance = 0.05;

Client::Options options() {
  Client::Options o;
  o.name = "sitl-test";
  o.reconnect = false;
  return o;
}

template <typename Done>
bool spin_until(Client& c, Done done, int timeout_ms = kWaitMs) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (!done()) {
    if (std::chrono::steady_clock::now() > end) return false;
    c.spin_once(10);
  }
  return true;
}

// The largest difference between what a ranger reads and what the room
// gives from the true pose; `what` lists the beams that differ.
struct RangeCheck {
  double worst = INFINITY;
  size_t checked = 0;
  std::string what;
};

RangeCheck check_laser(const client::RangerProxy& laser, const Pose2& truth) {
  RangeCheck r;
  if (laser.count() != 181) return r;
  r.worst = 0;
  const double ox = truth.x + kLaserX * std::cos(truth.a), oy = truth.y + kLaserX * std::sin(truth.a);
  std::ostringstream what;
  for (size_t i = 0; i < laser.count(); ++i) {
    const double expected = kRoom.range(ox, oy, truth.a + laser.bearing(i));
    if (expected > kLaserMax - 0.1) continue;  // beyond the scanner's reach
    const double error = std::fabs(laser.range(i) - expected);
    ++r.checked;
    r.worst = std::max(r.worst, error);
    if (error > kRangeTolerance)
      what << " beam " << i << ": " << laser.range(i) << " m, expected " << expected;
  }
  r.what = what.str();
  return r;
}

RangeCheck check_sonar(const client::RangerProxy& sonar, const Pose2& truth) {
  RangeCheck r;
  const drivers::p2os::RobotParams* robot = drivers::p2os::find_robot("p3dx-sh");
  if (sonar.count() != robot->sonar_count) return r;
  r.worst = 0;
  const double c = std::cos(truth.a), s = std::sin(truth.a);
  std::ostringstream what;
  for (size_t i = 0; i < robot->sonar_count; ++i) {
    const drivers::p2os::SonarPose& t = robot->sonar[i];
    const double x = truth.x + c * t.x - s * t.y, y = truth.y + s * t.x + c * t.y;
    const double expected = std::min(kRoom.range(x, y, truth.a + t.a), kSonarMax);
    const double error = std::fabs(sonar.range(i) - expected);
    ++r.checked;
    r.worst = std::max(r.worst, error);
    if (error > kRangeTolerance)
      what << " sonar " << i << ": " << sonar.range(i) << " m, expected " << expected;
  }
  r.what = what.str();
  return r;
}

}  // namespace

bool SimRig::start(const std::string& dir, std::string& error, bool links) {
  const std::string info = dir + "/emulated.txt";
  std::vector<std::string> argv = {TROUPE_SIM_BIN,
                                   std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/sitl_room.world",
                                   "--port",
                                   "0",
                                   "--no-ctrl",
                                   "--emulate",
                                   "r0=p2os,sicklms200",
                                   "--emulate-info",
                                   info};
  if (links) argv.insert(argv.end(), {"--emulate-links", dir});
  if (!sim.start(argv, dir, "troupe-sim", error)) return false;
  if (!sim.wait_for("listening on 127.0.0.1:", false, kWaitMs) ||
      !sim.wait_for("r0 sicklms200 ", false, kWaitMs)) {
    error = "troupe-sim did not come up; its output:\n" + sim.out() + sim.err();
    return false;
  }
  const std::string out = sim.out();
  const std::string needle = "listening on 127.0.0.1:";
  port = uint16_t(std::atoi(out.c_str() + out.find(needle) + needle.size()));
  // The info file holds the same lines as stdout.
  FILE* f = std::fopen(info.c_str(), "r");
  char robot[64], device[64], path[256];
  while (f && std::fscanf(f, "%63s %63s %255s", robot, device, path) == 3) {
    (std::string(device) == "p2os" ? p2os_path : sick_path) = path;
  }
  if (f) std::fclose(f);
  if (port == 0 || p2os_path.empty() || sick_path.empty()) {
    error = "troupe-sim printed no port or no pty paths:\n" + out;
    return false;
  }
  return true;
}

std::string node_config_json(const SimRig& rig) {
  return R"({
  "name": "sitl-pioneer", "listen": "127.0.0.1", "port": 0,
  "drivers": [
    { "driver_type": "p2os", "driver": { "port": ")" +
         rig.p2os_path + R"(" },
      "provides": ["position2d:0", "ranger:0", "power:0", "bumper:0"] },
    { "driver_type": "sicklms200", "driver": { "port": ")" +
         rig.sick_path + R"(", "baud": 38400, "pose_x": 0.16 },
      "provides": ["ranger:1"] }
  ]
}
)";
}

void drive_simulated_pioneer(uint16_t node_port, uint16_t sim_port,
                             const std::function<std::string()>& logs) {
  Client node("127.0.0.1", node_port, options());
  ASSERT_TRUE(node.connect()) << node.error();
  Client sim("127.0.0.1", sim_port, options());
  ASSERT_TRUE(sim.connect()) << sim.error();
  client::Position2dProxy base(node);
  client::RangerProxy sonar(node, 0), laser(node, 1);
  client::SimulationProxy simulation(sim);
  ASSERT_TRUE(base.is_open() && sonar.is_open() && laser.is_open()) << node.error();

  Pose2 truth;
  auto true_pose = [&] {
    EXPECT_TRUE(simulation.get_pose("r0", truth)) << sim.error();
    return truth;
  };
  // Waits until the robot stands still: the driver reports no motion and
  // the ground truth no longer changes between two looks.
  auto wait_stopped = [&] {
    ASSERT_TRUE(spin_until(node, [&] { return base.velocity().x == 0 && base.velocity().a == 0; })) << logs();
    for (Pose2 before = true_pose();; before = truth) {
      // Half a second of simulated time later (the clock troupe-sim pushes).
      const uint64_t then = simulation.sim_time_us() + 500000;
      ASSERT_TRUE(spin_until(sim, [&] { return simulation.sim_time_us() >= then; })) << logs();
      true_pose();
      if (before.x == truth.x && before.y == truth.y && before.a == truth.a) return;
    }
  };
  // Waits until both rangers read the room from the true pose.
  auto expect_ranges_match = [&](const char* when) {
    true_pose();
    RangeCheck l, s;
    spin_until(node, [&] {
      l = check_laser(laser, truth);
      s = check_sonar(sonar, truth);
      return l.worst <= kRangeTolerance && s.worst <= kRangeTolerance;
    });
    EXPECT_LE(l.worst, kRangeTolerance) << when << ", laser:" << l.what << "\n" << logs();
    EXPECT_GT(l.checked, 150u) << when;
    EXPECT_LE(s.worst, kRangeTolerance) << when << ", sonar:" << s.what << "\n" << logs();
  };

  // At rest: both rangers see the room as it is around the robot.
  expect_ranges_match("at the start");
  const Pose2 truth0 = truth, odom0 = base.pose();
  const float ahead0 = laser.range(90);

  // Forward 0.3 m/s until the odometry says 0.8 m, then stop.
  ASSERT_TRUE(base.set_velocity(0.3f, 0, 0));
  ASSERT_TRUE(spin_until(node, [&] { return base.x() - odom0.x > 0.8f; }))
      << "odometry x " << base.x() << " m\n"
      << logs();
  ASSERT_TRUE(base.set_velocity(0, 0, 0));
  wait_stopped();
  const Pose2 truth1 = true_pose(), odom1 = base.pose();
  const double moved = truth1.x - truth0.x;
  EXPECT_GT(moved, 0.75);
  // The odometry (1% error in this world) follows the ground truth.
  EXPECT_NEAR(odom1.x - odom0.x, moved, 0.02 * moved + 0.02);
  EXPECT_NEAR(odom1.y - odom0.y, truth1.y - truth0.y, 0.02);
  EXPECT_NEAR(truth1.a, truth0.a, 0.01);
  expect_ranges_match("after driving forward");
  // Straight ahead the wall came nearer by the distance driven.
  EXPECT_NEAR(ahead0 - laser.range(90), moved, 0.03);

  // Turn left in place until the odometry says 1 rad, then stop.
  ASSERT_TRUE(base.set_velocity(0, 0, 0.5f));
  ASSERT_TRUE(spin_until(node, [&] { return base.a() - odom1.a > 1.0f; }))
      << "odometry heading " << base.a() << " rad\n"
      << logs();
  ASSERT_TRUE(base.set_velocity(0, 0, 0));
  wait_stopped();
  const Pose2 truth2 = true_pose(), odom2 = base.pose();
  const double turned = truth2.a - truth1.a;
  EXPECT_GT(turned, 0.95);
  EXPECT_NEAR(odom2.a - odom1.a, turned, 0.02 * turned + 0.02);
  EXPECT_NEAR(truth2.x, truth1.x, 0.02);
  expect_ranges_match("after turning");
}

}  // namespace troupe::sitl
