// troupe-sim's SITL parts in-process: --emulate specs (and their errors),
// the simulated laser as the SICK emulator sees it, and the simulated
// Pioneer body (commands, odometry, its reset, stall, sonar).
#include "host-sim/troupe_sim/emulation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <tuple>

#include "host-sim/emulators/serial_line/room.h"
#include "tests/device_harness/device_harness.h"

namespace troupe::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
// sitl_room.world: inner wall faces at +-2.95 m; r0 starts at (-1.5, 0)
// facing +x with its laser 0.16 m ahead of its centre.
const emulators::Room kRoom{2.95, 2.95};

std::unique_ptr<World> load_room() {
  world::Diagnostics diags;
  auto world = World::load(std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/sitl_room.world", 1, diags);
  EXPECT_TRUE(world) << (diags.items().empty() ? "" : diags.items().front().str());
  return world;
}

std::string add_error(World& world, const std::string& spec) {
  Emulation e;
  std::string error;
  EXPECT_FALSE(e.add(world, spec, error)) << spec;
  return error;
}

TEST(SitlEmulation, BadSpecsAreRefusedSayingWhy) {
  auto world = load_room();
  ASSERT_TRUE(world);
  EXPECT_NE(add_error(*world, "r0").find("expected ROBOT=DEVICE[,DEVICE]"), std::string::npos);
  EXPECT_NE(add_error(*world, "=p2os").find("expected ROBOT=DEVICE"), std::string::npos);
  std::string e = add_error(*world, "r9=p2os");
  EXPECT_NE(e.find("--emulate r9=p2os: no robot 'r9' in the world (robots: r0"), std::string::npos) << e;
  EXPECT_NE(add_error(*world, "1=p2os").find("no robot '1'"), std::string::npos);
  e = add_error(*world, "r0=gps");
  EXPECT_NE(e.find("unknown device 'gps' (devices: p2os, sicklms200)"), std::string::npos) << e;
  EXPECT_NE(add_error(*world, "r0=p2os,").find("unknown device ''"), std::string::npos);
  EXPECT_NE(add_error(*world, "r0=odrive").find("not emulated by troupe-sim yet"), std::string::npos);
  EXPECT_NE(add_error(*world, "r0=p2os,p2os").find("device p2os named twice"), std::string::npos);

  // A refused spec leaves the others standing; a robot goes by number too.
  Emulation emulation;
  std::string error;
  EXPECT_FALSE(emulation.add(*world, "r0=sonar", error));
  ASSERT_TRUE(emulation.add(*world, "0=p2os,sicklms200", error)) << error;
  EXPECT_FALSE(emulation.add(*world, "r0=p2os", error));
  EXPECT_NE(error.find("robot r0 is already emulated"), std::string::npos) << error;
  ASSERT_TRUE(emulation.open("", error)) << error;
  std::vector<Emulation::Device> devices = emulation.devices();
  ASSERT_EQ(devices.size(), 2u);
  EXPECT_EQ(devices[0].kind, EmulatedKind::P2os);
  EXPECT_EQ(devices[1].kind, EmulatedKind::SickLms200);
  EXPECT_EQ(devices[0].path.rfind("/dev/pts/", 0), 0u) << devices[0].path;
  EXPECT_EQ(emulation.info(), "r0 p2os " + devices[0].path + "\nr0 sicklms200 " + devices[1].path + "\n");
}

TEST(SitlEmulation, ARobotWithoutLaserCannotBeAScanner) {
  troupe::testing::TempDir dir;
  const std::string path = dir.file("bare.world");
  FILE* f = std::fopen(path.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fputs("position ( name \"bare\" size [ 0.4 0.4 0.2 ] )\n", f);
  std::fclose(f);
  world::Diagnostics diags;
  auto world = World::load(path, 1, diags);
  ASSERT_TRUE(world);
  EXPECT_NE(add_error(*world, "bare=sicklms200").find("robot bare has no laser"), std::string::npos);
  // Its base alone is fine: a Pioneer without sonar reads nothing.
  Emulation emulation;
  std::string error;
  EXPECT_TRUE(emulation.add(*world, "bare=p2os", error)) << error;
}

TEST(SitlEmulation, LaserReadsTheWorldAtTheScannersBearings) {
  auto world = load_room();
  ASSERT_TRUE(world);
  SimLaser laser(*world, *find_laser(*world, 0));
  world->refresh_sensors();
  const double ox = -1.5 + 0.16;
  // 181 beams at 1 degree (the simulated beams exactly) and 401 at 0.25
  // degrees over 100 degrees (the nearest simulated beam each).
  for (auto [first_deg, step_deg, count] : {std::tuple{-90.0, 1.0, 181}, std::tuple{-50.0, 0.25, 401}}) {
    std::vector<float> ranges(static_cast<size_t>(count));
    laser.measure(first_deg * kPi / 180, step_deg * kPi / 180, ranges);
    for (int i = 0; i < count; ++i) {
      const double deg = first_deg + i * step_deg;
      if (std::fabs(std::fabs(deg - std::trunc(deg)) - 0.5) < 1e-6) continue;  // halfway: either beam
      const double nearest = std::round(deg) * kPi / 180;
      EXPECT_NEAR(ranges[size_t(i)], kRoom.range(ox, 0, nearest), 0.04) << "beam " << i << " of " << count;
    }
  }
  // Outside the simulated field of view there is no return.
  std::vector<float> behind(3);
  laser.measure(100 * kPi / 180, kPi / 180, behind);
  for (float r : behind) EXPECT_TRUE(std::isinf(r));
}

TEST(SitlEmulation, PioneerBodyDrivesTheRobotAndReportsItsOdometry) {
  auto world = load_room();
  ASSERT_TRUE(world);
  SimPioneerBody body(*world, 0);
  emulators::PioneerPose pose;
  const double track = 0.357;
  // The emulator's controllers run once per world step, on the odometry
  // that step reached: between steps there is nothing new to act on.
  EXPECT_EQ(body.observe(0.004, pose), 0) << "the first look";
  // 0.3 m/s on both wheels for a simulated second.
  for (int i = 0; i < 10; ++i) {
    body.move(0.3, 0.3, track, 0.1, pose);
    world->step();
    EXPECT_NEAR(body.observe(0.004, pose), 0.1, 1e-9) << "one world step of motion";
    EXPECT_EQ(body.observe(0.004, pose), 0) << "no step since";
  }
  EXPECT_NEAR(world->state(0).pose.x, -1.5 + 0.3, 0.03);
  EXPECT_NEAR(pose.x, 0.3, 0.03) << "odometry from the start pose";
  EXPECT_DOUBLE_EQ(pose.x, world->state(0).odometry.x);

  // The firmware zeroes its odometry (SETO): the world's follows.
  pose = {};
  EXPECT_EQ(body.observe(0.004, pose), 0);
  EXPECT_FALSE(body.move(0, 0, track, 0.1, pose));
  EXPECT_NEAR(world->state(0).odometry.x, 0, 1e-9);
  EXPECT_NEAR(pose.x, 0, 1e-9);

  // Sonar 3 (10 degrees left of ahead, at 0.166, 0.027) sees the east wall.
  emulators::PioneerSenses senses;
  world->refresh_sensors();
  const drivers::p2os::RobotParams& p3dx = *drivers::p2os::find_robot("p3dx-sh");
  body.sense(pose, p3dx, senses);
  const double x = world->state(0).pose.x;
  EXPECT_NEAR(senses.sonar_m[3], kRoom.range(x + 0.166, 0.027, 10 * kPi / 180), 0.04);

  // Driven into the wall, the robot stalls and says so.
  world->set_pose(0, {2.5, 0, 0});
  bool stalled = false;
  for (int i = 0; i < 40 && !stalled; ++i) {
    stalled = body.move(0.5, 0.5, track, 0.1, pose);
    world->step();
  }
  EXPECT_TRUE(stalled);
  EXPECT_LT(world->state(0).pose.x, 2.95 - 0.25);
}

}  // namespace
}  // namespace troupe::sim
