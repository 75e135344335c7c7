// A CARMEN log as a sequence of timed samples, ready to play: what the
// logreplay driver publishes and what troupe-mcl-eval feeds the localizer.
#pragma once

#include <vector>

#include "drivers/common_desktop/carmen_log.h"
#include "drivers/common_desktop/odometry_noise.h"

namespace troupe::desktop {

/// Where the odometry comes from.
enum class OdometrySource : uint8_t {
  /// The log's ODOM lines as they are.
  Log,
  /// Made from the scans' corrected poses (FLASER x y theta in a corrected
  /// log) by OdometrySynthesizer: one odometry sample per scan, at its time.
  Corrected,
};

struct ReplaySample {
  enum class Kind : uint8_t { Odometry, Scan, GroundTruth };
  Kind kind;
  /// Log time, s; never decreasing (a log line stamped earlier than the line
  /// before it is played at the earlier line's time).
  double time_s;
  /// Odometry or ground-truth pose: m, m, rad.
  Pose2 pose;
  /// Odometry velocities, m/s and rad/s (0 when the log has none).
  double tv = 0, rv = 0;
  /// Scan: index into CarmenLog::scans.
  uint32_t scan = 0;
};

struct TimelineOptions {
  OdometrySource odometry = OdometrySource::Log;
  OdometryNoise noise;
  /// Serve ground truth: TRUEPOS lines when the log has them, otherwise the
  /// scans' laser poses (a SLAM-corrected log, where they are corrected).
  bool ground_truth = false;
};

struct Timeline {
  std::vector<ReplaySample> samples;
  /// Lines whose time went backwards and were played at the previous time.
  size_t clamped = 0;
};

/// Orders the log's records into samples. Odometry precedes a scan of the
/// same instant. Draws the odometry noise from `rng` (Corrected only).
Timeline build_timeline(const CarmenLog& log, const TimelineOptions& options, Rng& rng);

}  // namespace troupe::desktop
