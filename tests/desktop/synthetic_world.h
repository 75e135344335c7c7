// A small made-up world for the desktop tests: a map with an asymmetric
// layout (so global localization has one answer), a ray caster that takes
// laser scans in it, and a writer for CARMEN logs of a drive through it.
#pragma once

#include <string>
#include <vector>

#include "drivers/common_desktop/occupancy_grid.h"
#include "drivers/common_desktop/particle_filter.h"

namespace troupe::desktop::testing {

/// 12 x 9 m at 0.05 m: outer walls, two rooms, a corridor and boxes, every
/// cell known. Origin at (-1, -1) so that map and cell coordinates differ.
OccupancyGrid make_test_map();

/// A laser of `beams` beams from -90 degrees, spaced as CARMEN logs SICK
/// scans: 180/(n-1) degrees for odd counts (181, 361: a beam on both edges),
/// 180/n for even counts (180, 360).
struct TestLaser {
  size_t beams = 181;
  double max_range = 8.0;  // m; no return reads max_range
  double start_angle() const { return -kPi / 2; }
  double angular_res() const { return kPi / double(beams % 2 ? beams - 1 : beams); }
};

/// Ranges seen from `pose` (m, m, rad): marching each beam through the grid
/// in steps of a fifth of a cell until an occupied cell or max_range.
std::vector<float> cast_scan(const OccupancyGrid& map, const Pose2& pose, const TestLaser& laser);

/// A drive through the test map: a loop of waypoints through both rooms,
/// sampled every `step_m` metres (or radians when turning on the spot).
std::vector<Pose2> test_route(double step_m = 0.25);

/// Writes a CARMEN log of the drive: per pose an ODOM line (the pose as
/// odometry) and a FLASER line (pose as both the laser pose and odom pose),
/// `period_s` apart. Returns the log text.
std::string write_carmen_log(const OccupancyGrid& map, const std::vector<Pose2>& poses,
                             const TestLaser& laser, double period_s);

/// A unique scratch folder under the system's temporary directory.
std::string scratch_dir();

}  // namespace troupe::desktop::testing
