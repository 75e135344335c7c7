// Localization accuracy on a recorded log with a known answer: the core of
// troupe-mcl-eval and of the accuracy benchmark. The map is drawn from the
// log's corrected scan poses, odometry is made from the same poses with
// seeded drift and slip, and the filter runs against the real scans; each
// estimate is compared with the corrected pose of its scan.
#pragma once

#include <cstdint>
#include <vector>

#include "drivers/common_desktop/log_map.h"
#include "drivers/common_desktop/particle_filter.h"
#include "drivers/common_desktop/replay_timeline.h"

namespace troupe::desktop {

/// MclParams with motion noise 0.01 (alpha1..4).
inline MclParams eval_mcl_params() {
  MclParams p;
  p.motion = {0.01, 0.01, 0.01, 0.01};
  return p;
}

struct EvalOptions {
  uint64_t seed = 1;
  LogMapOptions map;
  /// The filter. Its motion noise defaults to what the synthetic odometry
  /// below needs (about 10% per metre), not the driver's generous default
  /// for unknown robots.
  MclParams mcl = eval_mcl_params();
  OdometryNoise noise;
  /// Start from uniform particles instead of the first scan's pose.
  bool global = false;
  /// Pose tracking's initial spread around the first pose: m, rad.
  double initial_sigma_xy = 0.1;
  double initial_sigma_a = 0.05;
  /// The kidnapped robot on a log: from the scan with this index on, the
  /// replayed odometry is displaced by `kidnap_jump` (in the robot's frame
  /// at that scan: m, m, rad). The filter takes the jump as motion, so its
  /// belief lands away from the truth and it has to notice and recover.
  /// kNoKidnap: no jump.
  static constexpr size_t kNoKidnap = SIZE_MAX;
  size_t kidnap_scan = kNoKidnap;
  Pose2 kidnap_jump{0.0, 4.0, kPi / 2};
};

struct ScanError {
  double time_s;
  double trans_m;    // |estimate - corrected pose|, m
  double angle_rad;  // |heading error|, rad
  size_t particles;
  bool lost = false;  // the filter said it was lost after this scan
};

/// An estimate this far from the truth is off track, not a tracking error, m.
inline constexpr double kOffTrackM = 1.0;

struct EvalSummary {
  double mean_m = 0, max_m = 0, mean_deg = 0, max_deg = 0, within_10cm = 0;
  double mean_particles = 0;
  /// Shares of the scans: the filter said it was lost; the estimate was
  /// off track (over kOffTrackM) while the filter did not say so (a
  /// confident error).
  double said_lost = 0, unaware_off = 0;
  /// From `since_s` (the kidnapping, or the first scan): s until the filter
  /// first said it was lost, and s until the first scan from which the
  /// estimate stays on track (within kOffTrackM) to the end of the log.
  /// Negative: never.
  double since_s = 0, noticed_s = -1, recovered_s = -1;
};

struct EvalResult {
  OccupancyGrid map;
  std::vector<ScanError> scans;
  EvalSummary summary;
  /// Wall time spent in filter updates, s (for the per-scan cost).
  double filter_seconds = 0;
  /// Log time of the kidnap scan, s (0 without a kidnapping).
  double kidnap_time_s = 0;
};

/// Runs the evaluation. False with `error` when the log has no scans or the
/// map cannot be built.
bool evaluate_log(const CarmenLog& log, const EvalOptions& options, EvalResult& out, std::string& error);

/// Means, maxima, the share of scans within 0.1 m, the lost shares, and
/// the times to notice and to recover counted from the first scan at or
/// after `since_s` (s, log time).
EvalSummary summarize(const std::vector<ScanError>& scans, double since_s = 0);

}  // namespace troupe::desktop
