// Feature-based localization tests: the field's landmark table learned by
// the landmark_learner player, and a robot that drives on the field with
// noisy sensors.
#pragma once

#include <filesystem>
#include <string>

#include "tests/robocup/sim_fixture.h"

namespace troupe::robocup::test {

/// Goals, goal posts and corner posts only: the table's landmarks.
inline const char* kVision = "robots=0 ball=0 lines=0";

/// Learns the table into `path`: a noise-free omni camera on a 0.25 m grid
/// of 41 x 25 positions (the field and 0.5 m around it) at 8 headings.
inline void learn_field_table(const std::string& path) {
  std::filesystem::remove(path);
  const std::string world = R"(
world cycle=0.01 seed=5
field length=9 width=5
ball radius=0.11 mass=0.43 x=0 y=4
referee enabled=0
robot learner team=blue x=0 y=0 a=0 {
  shape circle r=0.2 z=0,0.6
  sensor omnivision name=omni range=12 z=0.7 )" +
                            std::string(kVision) +
                            R"(
  player landmark_learner out=")" +
                            path + R"(" step=0.25 headings=8 margin=0.5
})";
  std::string error;
  auto sim = make_sim(world, error);
  ASSERT_TRUE(sim) << error;
  ASSERT_TRUE(sim->problems().empty()) << sim->problems().front();
  // A pose a cycle, and one more to write the file.
  sim->run_for(41 * 25 * 8 * 0.01 + 0.05);
  ASSERT_TRUE(std::filesystem::exists(path)) << "the learner wrote no table";
}

/// A Pioneer with noisy odometry and noisy omni-vision (every 4 cycles),
/// robot 0, at (-2, 1) heading 0.5 rad; no player: drive it with commands.
inline std::string runner_world() {
  return R"(
world cycle=0.01 seed=8
field length=9 width=5
ball radius=0.11 mass=0.43 x=0 y=4
referee enabled=0
robot runner team=blue x=-2 y=1 a=0.5 {)" +
         pioneer_block(R"(
  motion diff_drive max_speed=2 max_turn=6 accel=2.5 turn_accel=15
  sensor odometry translation_noise=0.03 rotation_noise=0.03 drift=0.02
  sensor omnivision name=omni range=12 z=0.7 range_noise=0.03 bearing_noise=0.02 period=4 )" +
                       std::string(kVision) + "\n") +
         "}\n";
}

}  // namespace troupe::robocup::test
