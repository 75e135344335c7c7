#include "drivers/common_desktop/mcl_eval.h"

#include <algorithm>
#include <chrono>

namespace troupe::desktop {

EvalSummary summarize(const std::vector<ScanError>& scans) {
  EvalSummary s;
  if (scans.empty()) return s;
  size_t within = 0;
  for (const ScanError& e : scans) {
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
  for (const ReplaySample& s : timeline.samples) {
    if (s.kind == ReplaySample::Kind::Odometry) {
      odom = s.pose;
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
                         std::fabs(wrap_angle(best.a - l.laser_pose.a)), filter.particles().size()});
  }
  out.summary = summarize(out.scans);
  return true;
}

}  // namespace troupe::desktop
