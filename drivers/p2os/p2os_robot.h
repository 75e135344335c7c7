// What differs between Pioneer models: the conversion factors from robot
// counts to SI units, speed limits, footprint and the sonar ring. Selected
// by the subclass the robot names in its SYNC2 reply ("p3dx-sh") or by the
// driver's `model` option.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace troupe::drivers::p2os {

/// A sonar transducer on the robot: m, m, rad (heading of its beam).
struct SonarPose {
  float x, y, a;
};

struct RobotParams {
  /// Subclass as the robot reports it, e.g. "p3dx-sh".
  const char* subclass;
  /// rad per heading count.
  double angle_conv;
  /// mm per position count.
  double dist_conv;
  /// mm/s per wheel velocity count.
  double vel_conv;
  /// mm per sonar range count.
  double range_conv;
  /// Turn rate per wheel speed difference: w = (v_right - v_left) / 2 *
  /// diff_conv, rad/s from mm/s (1 / half the wheel track, 1/mm).
  double diff_conv;
  /// mm/s per VEL2 unit.
  int vel2_divisor;
  /// Fastest forward speed the firmware allows, m/s.
  float max_speed;
  /// Fastest turn, rad/s.
  float max_turn_rate;
  /// Footprint: length and width, m.
  float length, width;
  /// Longest sonar range reported, m.
  float sonar_max_range;
  size_t sonar_count;
  const SonarPose* sonar;
};

/// The parameters for `subclass` (case-insensitive), or nullptr.
const RobotParams* find_robot(std::string_view subclass);
/// "p3dx-sh, p3dx": for error messages.
std::string known_robots();

}  // namespace troupe::drivers::p2os
