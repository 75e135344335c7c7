#include "drivers/common_desktop/replay_timeline.h"

#include <algorithm>

namespace troupe::desktop {

Timeline build_timeline(const CarmenLog& log, const TimelineOptions& opt, Rng& rng) {
  Timeline out;
  OdometrySynthesizer synth(opt.noise, rng);
  bool scans_as_truth = opt.ground_truth && log.true_poses.empty();
  double last_t = -1e300;
  Pose2 last_truth;
  double last_truth_t = 0;
  bool have_truth = false;
  auto stamp = [&](double t) {
    if (t < last_t) {
      ++out.clamped;
      return last_t;
    }
    return last_t = t;
  };
  for (const RecordRef& ref : log.order) {
    switch (ref.kind) {
      case RecordKind::Odometry: {
        if (opt.odometry != OdometrySource::Log) break;
        const OdomReading& o = log.odometry[ref.index];
        ReplaySample s{ReplaySample::Kind::Odometry, stamp(o.time_s), o.pose, o.tv, o.rv, 0};
        out.samples.push_back(s);
        break;
      }
      case RecordKind::Laser: {
        const LaserReading& l = log.scans[ref.index];
        double t = stamp(l.time_s);
        if (opt.odometry == OdometrySource::Corrected) {
          ReplaySample s{ReplaySample::Kind::Odometry, t, synth.next(l.laser_pose, rng), 0, 0, 0};
          if (have_truth && t > last_truth_t) {
            Pose2 d = relative(last_truth, l.laser_pose);
            s.tv = std::copysign(std::hypot(d.x, d.y), d.x) / (t - last_truth_t);
            s.rv = d.a / (t - last_truth_t);
          }
          out.samples.push_back(s);
        }
        out.samples.push_back({ReplaySample::Kind::Scan, t, l.laser_pose, 0, 0, ref.index});
        if (scans_as_truth)
          out.samples.push_back({ReplaySample::Kind::GroundTruth, t, l.laser_pose, 0, 0, 0});
        last_truth = l.laser_pose;
        last_truth_t = t;
        have_truth = true;
        break;
      }
      case RecordKind::TruePose: {
        if (!opt.ground_truth) break;
        const TruePoseReading& r = log.true_poses[ref.index];
        out.samples.push_back({ReplaySample::Kind::GroundTruth, stamp(r.time_s), r.true_pose, 0, 0, 0});
        break;
      }
    }
  }
  return out;
}

}  // namespace troupe::desktop
