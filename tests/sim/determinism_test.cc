// Determinism: the same world and seed give byte-identical trajectory logs;
// another seed gives another run; and a sensor's noise does not depend on
// which other sensors are read, or in which order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "host-sim/sim/trajectory_log.h"
#include "host-sim/sim/world.h"
#include "tests/sim/scenes.h"
#include "tests/sim/temp_dir.h"

namespace troupe::sim {
namespace {

// 24 robots with noisy lasers in a room with a pillar.
WorldDesc crowd() {
  WorldDesc d = test::room(6, 4);
  d.statics[0].polygons.push_back(test::box(-0.5, -0.5, 0.5, 0.5));
  for (int i = 0; i < 24; ++i) {
    std::string name = "r";  // appended: GCC 12 -O3 warns falsely (-Wrestrict) on "r" + std::string
    name.append(std::to_string(i));
    RobotDesc r = test::robot(name, {-5 + (i % 8) * 1.4, -3 + (i / 8) * 2.5 + 0.3, i * 0.7}, 0.3);
    r.velocity[0] = {-0.5, 0.5};
    r.acceleration[0] = {-1, 1};
    RangerDesc laser = test::laser(31, kPi, 3.0);
    laser.transducers[0].noise_variance = 0.0025;
    laser.transducers[0].noise_proportional = 0.02;
    laser.transducers[0].noise_angle = 0.01;
    r.rangers.push_back(laser);
    r.localization = Localization::Odom;
    d.robots.push_back(r);
  }
  return d;
}

// A wanderer whose every decision depends on the noisy ranges.
void wander(World& w) {
  for (RobotId i = 0; i < w.robot_count(); ++i) {
    RangerView v = w.ranger(w.robot(i).rangers.first);
    const size_t n = v.ranges.size();
    float right = *std::min_element(v.ranges.begin(), v.ranges.begin() + n / 2);
    float left = *std::min_element(v.ranges.begin() + n / 2 + 1, v.ranges.end());
    float ahead = v.ranges[n / 2];
    double turn = left < right ? -0.8 : 0.8;
    w.command(i,
              ahead < 0.6 ? Command::velocity(0, 0, turn) : Command::velocity(0.4, 0, 0.3 * (left - right)));
  }
}

struct RunResult {
  std::string log;
  int moved = 0;  // robots that ended more than 1 m from their start
};

RunResult run(uint64_t seed, int steps) {
  RunResult out;
  World w(crowd(), Random(seed));
  for (RobotId i = 0; i < w.robot_count(); ++i)
    w.set_wanted({SensorKind::Ranger, w.robot(i).rangers.first}, true);
  w.refresh_sensors();
  for (int s = 0; s < steps; ++s) {
    wander(w);
    w.step();
    out.log += TrajectoryLog::format(w);
  }
  for (RobotId i = 0; i < w.robot_count(); ++i) {
    const Pose& p = w.state(i).pose;
    const Pose& start = w.desc().robots[i].pose;
    out.moved += std::hypot(p.x - start.x, p.y - start.y) > 1.0;
  }
  return out;
}

TEST(Determinism, SameSeedSameTrajectoryBytes) {
  const RunResult a = run(5, 300), b = run(5, 300), c = run(6, 300);
  ASSERT_EQ(a.log.size(), b.log.size());
  EXPECT_TRUE(a.log == b.log);
  EXPECT_FALSE(a.log == c.log);
  // The run did something worth comparing: most robots travelled.
  EXPECT_GT(a.moved, 12);
}

TEST(Determinism, TrajectoryLogFilesAreByteIdentical) {
  troupe::test::TempDir dir;
  for (const char* name : {"a.csv", "b.csv"}) {
    World w(crowd(), Random(11));
    for (RobotId i = 0; i < w.robot_count(); ++i)
      w.set_wanted({SensorKind::Ranger, w.robot(i).rangers.first}, true);
    TrajectoryLog log;
    std::string error;
    ASSERT_TRUE(log.open(dir.path(name), error)) << error;
    for (int s = 0; s < 100; ++s) {
      wander(w);
      w.step();
      log.record(w);
    }
    ASSERT_TRUE(log.close());
  }
  auto slurp = [&](const char* name) {
    std::ifstream in(dir.path(name), std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  const std::string a = slurp("a.csv");
  EXPECT_EQ(a.substr(0, 17), "time,robot,x,y,a\n");
  EXPECT_TRUE(a == slurp("b.csv"));
  EXPECT_EQ(std::count(a.begin(), a.end(), '\n'), 1 + 100 * 24);
}

TEST(Determinism, NoiseDoesNotDependOnWhichSensorsAreRead) {
  // Open-loop commands, so poses do not depend on the sensors; then one
  // world computes every ranger, the other only robot 7's.
  World all(crowd(), Random(3)), one(crowd(), Random(3));
  for (RobotId i = all.robot_count(); i-- > 0;) {
    all.set_wanted({SensorKind::Ranger, all.robot(i).rangers.first}, true);
  }
  const uint32_t seven = one.robot(7).rangers.first;
  one.set_wanted({SensorKind::Ranger, seven}, true);
  for (int s = 0; s < 50; ++s) {
    for (RobotId i = 0; i < all.robot_count(); ++i) {
      all.command(i, Command::velocity(0.3, 0, 0.2 * ((i + s / 10) % 3 - 1.0)));
      one.command(i, Command::velocity(0.3, 0, 0.2 * ((i + s / 10) % 3 - 1.0)));
    }
    all.step();
    one.step();
    RangerView a = all.ranger(seven), b = one.ranger(seven);
    ASSERT_TRUE(std::equal(a.ranges.begin(), a.ranges.end(), b.ranges.begin(), b.ranges.end()))
        << "step " << s;
    EXPECT_EQ(one.ranger(one.robot(6).rangers.first).step, UINT64_MAX);  // never computed
  }
}

}  // namespace
}  // namespace troupe::sim
