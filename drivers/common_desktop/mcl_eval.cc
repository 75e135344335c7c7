#include "drivers/common_desktop/mcl_eval.h"

#include <algorithm>
#include <chrono>

namespace troupe::desktop {

EvalSummary summarize(const std::vector<ScanError>& scans, double since_s) {
  EvalSummary s;
  if (scans.empty()) return s;
  size_t within = 0, lost = 0, unaware = 0;
  for (const ScanError& e : scans) {
    lost += e.lost ? 1 : 0;
    unaware += !e.lost && e.trans_m > kOffTrackM ? 1 : 0;
    s.mean_m += e.trans_m;
    s.mean_deg += e.angle_rad;
    s.max_m = std::max(s.max_m, e.trans_m);
    s.max_deg = std::max(s.max_deg, e.angle_rad);
    s.mean_particles += double(e.particles);
    within += e.trans_m < 0.1 ? 1 : 0;
  }
  double n = double(scans.size());
  s.mean_m /= n;
  s.mean_deg *= 180.0 / kPi / n;
  s.max_deg *= 180.0 / kPi;
  s.mean_particles /= n;
  s.within_10cm = double(within) / n;
  s.said_lost = double(lost) / n;
  s.unaware_off = double(unaware) / n;
  // Recovery: from the first scan at or after since_s.
  size_t from = 0;
  while (from < scans.size() && scans[from].time_s < since_s) ++from;
  if (from == scans.size()) return s;
  s.since_s = scans[from].time_s;
  for (size_t i = from; i < scans.size() && s.noticed_s < 0; ++i) {
    if (scans[i].lost) s.noticed_s = scans[i].time_s - s.since_s;
  }
  size_t settled = scans.size();
  while (settled > from && scans[settled - 1].trans_m <= kOffTrackM) --settled;
  if (settled < scans.size()) s.recovered_s = scans[settled].time_s - s.since_s;
  return s;
}

bool evaluate_log(const CarmenLog& log, const EvalOptions& opt, EvalResult& out, std::string& error) {
  if (log.scans.empty()) {
    error = "the log has no FLASER or ROBOTLASER1 scans";
    return false;
  }
  if (!build_log_map(log.scans, opt.map, out.map, error)) return false;
  // Two streams from one seed: the odometry noise and the filter's draws.
  Rng noise_rng(opt.seed);
  Rng filter_rng(opt.seed ^ 0x9e3779b97f4a7c15ull);
  TimelineOptions topt;
  topt.odometry = OdometrySource::Corrected;
  topt.noise = opt.noise;
  Timeline timeline = build_timeline(log, topt, noise_rng);

  ParticleFilter filter(out.map, opt.mcl);
  if (opt.global) {
    filter.init_global(filter_rng);
  } else {
    const Pose2& first = log.scans.front().laser_pose;
    Eigen::Vector3d var(opt.initial_sigma_xy * opt.initial_sigma_xy,
                        opt.initial_sigma_xy * opt.initial_sigma_xy,
                        opt.initial_sigma_a * opt.initial_sigma_a);
    filter.init_pose(first, var.asDiagonal(), filter_rng);
  }
  out.scans.clear();
  Pose2 odom;
  bool have_odom = false;
  // The kidnapping: every odometry pose from the kidnap scan's on is
  // composed with `jump_frame`, which moves that scan's odometry pose by
  // kidnap_jump in its own frame; the motion between later poses is kept.
  bool kidnapped = false;
  Pose2 jump_frame;
  double kidnap_time_s = 0;
  for (const ReplaySample& s : timeline.samples) {
    if (s.kind == ReplaySample::Kind::Scan && s.scan == opt.kidnap_scan && !kidnapped && have_odom) {
      kidnapped = true;
      kidnap_time_s = s.time_s;
      jump_frame = compose(compose(odom, opt.kidnap_jump), relative(odom, Pose2{}));
      odom = compose(jump_frame, odom);  // this scan's odometry arrived before it
    }
    if (s.kind == ReplaySample::Kind::Odometry) {
      odom = kidnapped ? compose(jump_frame, s.pose) : s.pose;
      have_odom = true;
      continue;
    }
    if (s.kind != ReplaySample::Kind::Scan || !have_odom) continue;
    const LaserReading& l = log.scans[s.scan];
    ScanView view{l.start_angle, l.angular_res, l.max_range, l.ranges};
    auto t0 = std::chrono::steady_clock::now();
    filter.update(odom, view, filter_rng);
    out.filter_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    Pose2 best = filter.best();
    out.scans.push_back({s.time_s, distance(best, l.laser_pose),
                         std::fabs(wrap_angle(best.a - l.laser_pose.a)), filter.particles().size(),
                         filter.lost()});
  }
  out.kidnap_time_s = kidnap_time_s;
  out.summary = summarize(out.scans, kidnapped ? kidnap_time_s : 0.0);
  return true;
}

}  // namespace troupe::desktop
