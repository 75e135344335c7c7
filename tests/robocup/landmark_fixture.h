// Feature-based localization tests: the field's landmark table learned by
// the landmark_learner player, and a robot that drives on the field with
// noisy sensors.
#pragma once

#include <filesystem>
#include <string>

#include "tests/robocup/sim_fixture.h"

namespace troupe::robocup::test {

/// Goals, goal posts and corner posts only: the table's landmarks.
inline const char* kVision = "robots 0 ball 0 lines 0";

/// Learns the table into `path`: a noise-free omni camera on a 0.25 m grid
/// of 41 x 25 positions (the field and 0.5 m around it) at 8 headings.
inline void learn_field_table(const std::string& path) {
  std::filesystem::remove(path);
  const std::string world = R"(
interval_sim 10
seed 5
robocup_field ( length 9 width 5 )
ball ( radius 0.11 mass 0.43 pose [0 4 0 0] )
referee ( enabled 0 )
)" + robot("learner", "blue", 0, 0, 0, R"(
  shape ( kind "circle" r 0.2 z [0 0.6] )
  sensor_plugin ( plugin "omnivision" name "omni" range 12 z 0.7 )" + std::string(kVision) + R"( )
  player ( plugin "landmark_learner" out ")" + path + R"(" step 0.25 headings 8 margin 0.5 )
)");
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
interval_sim 10
seed 8
robocup_field ( length 9 width 5 )
ball ( radius 0.11 mass 0.43 pose [0 4 0 0] )
referee ( enabled 0 )
)" + robot("runner", "blue", -2, 1, 0.5, pioneer_block(R"(
  motion_plugin ( plugin "diff_drive" max_speed 2 max_turn 6 accel 2.5 turn_accel 15 )
  sensor_plugin ( plugin "odometry" translation_noise 0.03 rotation_noise 0.03 drift 0.02 )
  sensor_plugin ( plugin "omnivision" name "omni" range 12 z 0.7 range_noise 0.03 bearing_noise 0.02 period 4 )" +
                       std::string(kVision) + " )\n"));
}

}  // namespace troupe::robocup::test
