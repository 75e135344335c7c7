// CARMEN log files (Carnegie Mellon's robot log format; ../shared/protocols.md
// in the project notes): one record per text line, readings in metres and
// radians, a timestamp in seconds near the end of each line.
//
// Read: ODOM, FLASER, ROBOTLASER1 and TRUEPOS. Any other line type (PARAM,
// SYNC, NEFF, RLASER, ...) is counted and skipped. A malformed line of a known
// type is reported with its line number and skipped; the rest of the log is
// still read. gzip-compressed logs are read through zlib, which reads plain
// text files unchanged, so one reader serves both.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "drivers/common_desktop/pose2.h"

namespace troupe::desktop {

/// An ODOM line: the odometry pose and velocities.
struct OdomReading {
  double time_s = 0;  // log timestamp, s
  uint32_t line = 0;  // 1-based line number in the file
  Pose2 pose;         // odometry frame: m, m, rad
  double tv = 0;      // forward velocity, m/s
  double rv = 0;      // turn rate, rad/s
};

/// A laser scan (FLASER or ROBOTLASER1).
struct LaserReading {
  double time_s = 0;
  uint32_t line = 0;
  double start_angle = 0;     // bearing of ranges[0] in the laser frame, rad
  double angular_res = 0;     // angle between beams, rad
  double max_range = 0;       // a range at or beyond it is "no return", m
  std::vector<float> ranges;  // m
  /// Pose of the laser when the scan was taken (FLASER x y theta;
  /// ROBOTLASER1 laser_x..). In a SLAM-corrected log this is the corrected
  /// pose: m, m, rad.
  Pose2 laser_pose;
  /// Pose of the robot (FLASER odom_*; ROBOTLASER1 robot_*): m, m, rad.
  Pose2 robot_pose;
};

/// A TRUEPOS line (simulator logs): the true pose and the odometry pose.
struct TruePoseReading {
  double time_s = 0;
  uint32_t line = 0;
  Pose2 true_pose;
  Pose2 odom_pose;
};

enum class RecordKind : uint8_t { Odometry, Laser, TruePose };

/// One record in file order: which vector it is in, and where.
struct RecordRef {
  RecordKind kind;
  uint32_t index;
};

/// How to read FLASER lines, which carry neither their field of view nor
/// their maximum range.
struct CarmenOptions {
  /// FLASER field of view, rad. With n beams the spacing is fov/(n-1) for odd
  /// n (a beam on both edges: 181, 361) and fov/n for even n (180, 360), the
  /// convention of SICK scanners logged by CARMEN.
  double flaser_fov = 3.14159265358979323846;
  /// Bearing of the first FLASER beam, rad.
  double flaser_start_angle = -3.14159265358979323846 / 2;
  /// FLASER range meaning "no return" unless the log's PARAM
  /// robot_front_laser_max says otherwise, m.
  double flaser_max_range = 50.0;
  /// Malformed lines kept as messages (all are counted).
  size_t max_error_messages = 100;
};

struct CarmenLog {
  std::vector<OdomReading> odometry;
  std::vector<LaserReading> scans;
  std::vector<TruePoseReading> true_poses;
  /// Every record read, in file order.
  std::vector<RecordRef> order;
  /// "FILE:LINE: what", one per malformed line (at most max_error_messages).
  std::vector<std::string> errors;
  size_t error_count = 0;
  /// Lines of types this reader does not use (PARAM, NEFF, ...).
  size_t skipped_lines = 0;
  size_t line_count = 0;
};

/// Parses log text. `name` prefixes error messages.
CarmenLog parse_carmen(std::string_view text, std::string_view name, const CarmenOptions& options = {});

/// Reads a log file, plain or gzip-compressed. False with `error` when the
/// file cannot be read at all (malformed lines are not failures: see
/// CarmenLog::errors).
bool read_carmen(const std::string& path, CarmenLog& out, std::string& error,
                 const CarmenOptions& options = {});

/// Reads a whole file, decompressing gzip (zlib reads plain files as they are).
bool read_maybe_gzip(const std::string& path, std::string& out, std::string& error);

}  // namespace troupe::desktop
