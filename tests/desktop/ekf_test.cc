// The fusion EKF: consistency (NEES) on simulated trajectories, late and
// out-of-order fixes, gating, landmarks.
#include "drivers/common_desktop/ekf.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "drivers/common_desktop/rng.h"

namespace troupe::desktop {
namespace {

// Wilson-Hilferty: the p-quantile of chi-square with n dof, given the
// standard normal quantile z of p. Accurate to ~0.1% for n >= 30.
double chi2_quantile(double n, double z) {
  double a = 2.0 / (9.0 * n);
  return n * std::pow(1 - a + z * std::sqrt(a), 3);
}

struct Step {
  double t;
  Pose2 truth;
  Pose2 odom;
  double gyro;
  bool fix;
  Pose2 fix_pose;
};

// A trajectory drawn from the filter's own process model, with odometry
// speeds, gyro and fixes drawn from the measurement models.
std::vector<Step> simulate(const EkfParams& p, double gyro_sigma, const Eigen::Matrix3d& fix_cov, int steps,
                           double dt, int fix_every, Rng& rng) {
  Eigen::Matrix3d fix_l = fix_cov.llt().matrixL();
  std::vector<Step> out;
  Pose2 x{0, 0, 0.3}, odom{};
  double v = 0.5, w = 0.1;
  for (int k = 1; k <= steps; ++k) {
    x.x += v * std::cos(x.a) * dt + gaussian(rng, std::sqrt(p.pose_psd_xy * dt));
    x.y += v * std::sin(x.a) * dt + gaussian(rng, std::sqrt(p.pose_psd_xy * dt));
    x.a = wrap_angle(x.a + w * dt + gaussian(rng, std::sqrt(p.pose_psd_a * dt)));
    v += gaussian(rng, std::sqrt(p.accel_psd * dt));
    w += gaussian(rng, std::sqrt(p.turn_accel_psd * dt));
    Step s;
    s.t = k * dt;
    s.truth = x;
    // Odometry that moves forward by the measured speed, then turns: the
    // filter reads (chord / dt, turn / dt) back from it.
    double vm = v + gaussian(rng, p.odom_speed_sigma), wm = w + gaussian(rng, p.odom_turn_sigma);
    odom = compose(odom, {vm * dt, 0, wm * dt});
    s.odom = odom;
    s.gyro = w + gaussian(rng, gyro_sigma);
    s.fix = k % fix_every == 0;
    Eigen::Vector3d n = fix_l * Eigen::Vector3d(gaussian(rng, 1), gaussian(rng, 1), gaussian(rng, 1));
    s.fix_pose = {x.x + n(0), x.y + n(1), wrap_angle(x.a + n(2))};
    out.push_back(s);
  }
  return out;
}

double pose_nees(const PoseEkf& f, const Pose2& truth) {
  Eigen::Vector3d e(f.state()(0) - truth.x, f.state()(1) - truth.y, wrap_angle(f.state()(2) - truth.a));
  Eigen::Matrix3d p = f.covariance().topLeftCorner<3, 3>();
  return e.dot(p.ldlt().solve(e));
}

TEST(Ekf, ConsistentOnSimulatedTrajectories) {
  EkfParams p;
  p.accel_psd = 0.05;
  p.turn_accel_psd = 0.02;
  p.odom_speed_sigma = 0.05;
  p.odom_turn_sigma = 0.03;
  p.gate = 0;  // every fix is drawn from the model: nothing to refuse
  const double gyro_sigma = 0.01, dt = 0.1;
  const Eigen::Matrix3d fix_cov = Eigen::Vector3d(0.05 * 0.05, 0.05 * 0.05, 0.03 * 0.03).asDiagonal();
  const Eigen::Matrix3d start_cov = Eigen::Vector3d(0.01, 0.01, 0.004).asDiagonal();
  const int runs = 50, steps = 300;
  std::vector<double> nees(steps, 0.0);
  Rng rng(2024);
  for (int run = 0; run < runs; ++run) {
    std::vector<Step> traj = simulate(p, gyro_sigma, fix_cov, steps, dt, 10, rng);
    PoseEkf f(p);
    // Start from a pose drawn from the start covariance around the truth.
    Eigen::Vector3d n =
        start_cov.llt().matrixL() * Eigen::Vector3d(gaussian(rng, 1), gaussian(rng, 1), gaussian(rng, 1));
    Pose2 x0{n(0), n(1), 0.3 + n(2)};
    f.reset(0.0, x0, start_cov);
    // The truth starts with speeds 0.5 m/s and 0.1 rad/s; the filter learns them.
    f.add_odometry(0.0, {});
    for (int k = 0; k < steps; ++k) {
      const Step& s = traj[size_t(k)];
      ASSERT_EQ(f.add_odometry(s.t, s.odom), PoseEkf::Outcome::Applied);
      ASSERT_EQ(f.add_yaw_rate(s.t, s.gyro, gyro_sigma), PoseEkf::Outcome::Applied);
      if (s.fix) {
        ASSERT_EQ(f.add_pose_fix(s.t, s.fix_pose, fix_cov), PoseEkf::Outcome::Applied);
      }
      nees[size_t(k)] += pose_nees(f, s.truth) / runs;
    }
  }
  // runs * mean NEES ~ chi-square with 3 * runs dof: the two-sided 95% band.
  double lo = chi2_quantile(3.0 * runs, -1.95996) / runs, hi = chi2_quantile(3.0 * runs, 1.95996) / runs;
  // Skip the first second: the speeds start unknown (variance 1).
  int inside = 0, counted = 0;
  double mean = 0;
  for (int k = 10; k < steps; ++k, ++counted) {
    inside += nees[size_t(k)] >= lo && nees[size_t(k)] <= hi;
    mean += nees[size_t(k)];
  }
  mean /= counted;
  // Over seeds 1..7 and 2024 of the generator these 50 runs gave 82..98 %
  // inside and a mean of 2.68..3.28: the bounds hold a consistent filter with
  // room for the draw, and fail one whose covariance is off by a third.
  EXPECT_GT(double(inside) / counted, 0.80) << "band [" << lo << ", " << hi << "], mean NEES " << mean;
  EXPECT_GT(mean, 2.6);
  EXPECT_LT(mean, 3.4);
}

TEST(Ekf, LateFixesGiveTheSameStateAsFixesInOrder) {
  EkfParams p;
  Rng rng(9);
  const Eigen::Matrix3d fix_cov = Eigen::Vector3d(0.01, 0.01, 0.003).asDiagonal();
  std::vector<Step> traj = simulate(p, 0.02, fix_cov, 100, 0.05, 7, rng);
  PoseEkf in_order(p), late(p);
  for (PoseEkf* f : {&in_order, &late}) {
    f->reset(0.0, {0, 0, 0.3}, Eigen::Vector3d(0.01, 0.01, 0.01).asDiagonal());
    f->add_odometry(0.0, {});
  }
  std::vector<const Step*> waiting;
  size_t late_applied = 0;
  for (size_t k = 0; k < traj.size(); ++k) {
    const Step& s = traj[k];
    in_order.add_odometry(s.t, s.odom);
    in_order.add_yaw_rate(s.t, s.gyro, 0.02);
    if (s.fix) in_order.add_pose_fix(s.t, s.fix_pose, fix_cov);
    late.add_odometry(s.t, s.odom);
    late.add_yaw_rate(s.t, s.gyro, 0.02);
    // Fixes reach `late` four samples after they were taken, newest first
    // when two are waiting (out of order).
    if (s.fix) waiting.push_back(&s);
    if (k % 8 == 3) {
      for (auto it = waiting.rbegin(); it != waiting.rend(); ++it) {
        PoseEkf::Outcome o = late.add_pose_fix((*it)->t, (*it)->fix_pose, fix_cov);
        late_applied += o == PoseEkf::Outcome::AppliedLate;
      }
      waiting.clear();
    }
  }
  for (const Step* s : waiting) {
    late_applied += late.add_pose_fix(s->t, s->fix_pose, fix_cov) == PoseEkf::Outcome::AppliedLate;
  }
  EXPECT_GT(late_applied, 5u);
  EXPECT_EQ(late.late_count(), late_applied);
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(late.state()(i), in_order.state()(i), 1e-9) << i;
  }
  EXPECT_TRUE(late.covariance().isApprox(in_order.covariance(), 1e-9));
}

TEST(Ekf, FixesOlderThanTheHistoryAreDroppedAndOutliersGated) {
  EkfParams p;
  p.history_s = 1.0;
  p.max_gated = 3;
  PoseEkf f(p);
  Eigen::Matrix3d cov = Eigen::Vector3d(0.01, 0.01, 0.01).asDiagonal();
  EXPECT_EQ(f.add_odometry(0.0, {}), PoseEkf::Outcome::NotReady);
  EXPECT_EQ(f.add_pose_fix(0.0, {1, 2, 0}, cov), PoseEkf::Outcome::Applied);  // starts the filter
  for (int k = 1; k <= 30; ++k) f.add_odometry(0.1 * k, {0.05 * k, 0, 0});
  Pose2 before = f.pose();
  EXPECT_EQ(f.add_pose_fix(0.5, {1.1, 2, 0}, cov), PoseEkf::Outcome::TooOld);
  EXPECT_EQ(f.dropped_count(), 1u);
  EXPECT_EQ(f.pose().x, before.x);
  // 5 m off: an outlier, three times refused, then believed.
  Pose2 far{before.x + 5, before.y, 0};
  EXPECT_EQ(f.add_pose_fix(3.0, far, cov), PoseEkf::Outcome::Gated);
  EXPECT_EQ(f.add_pose_fix(3.0, far, cov), PoseEkf::Outcome::Gated);
  EXPECT_EQ(f.pose().x, before.x);
  EXPECT_EQ(f.add_pose_fix(3.0, far, cov), PoseEkf::Outcome::Applied);
  EXPECT_NEAR(f.pose().x, far.x, 1e-9);
  EXPECT_EQ(f.gated_count(), 3u);
  // Garbage is refused without touching the state.
  Eigen::Matrix3d bad = cov;
  bad(0, 0) = -1;
  EXPECT_EQ(f.add_pose_fix(3.1, {0, 0, 0}, bad), PoseEkf::Outcome::Invalid);
  EXPECT_EQ(f.add_pose_fix(3.1, {NAN, 0, 0}, cov), PoseEkf::Outcome::Invalid);
  EXPECT_EQ(f.add_yaw_rate(3.1, 0.1, 0), PoseEkf::Outcome::Invalid);
  EXPECT_EQ(f.add_odometry(NAN, {}), PoseEkf::Outcome::Invalid);
  EXPECT_NEAR(f.pose().x, far.x, 1e-9);
}

TEST(Ekf, LandmarkSightingsLocateAStandingRobot) {
  EkfParams p;
  PoseEkf f(p);
  Pose2 truth{2.0, 1.0, 0.7};
  f.reset(0.0, {2.4, 0.7, 0.9}, Eigen::Vector3d(0.25, 0.25, 0.1).asDiagonal());
  const Pose2 marks[] = {{5, 1, 3.0}, {2, 4, -1.0}, {0, 0, 0.5}};
  Rng rng(4);
  const double s = 0.05;
  Eigen::Matrix3d cov = Eigen::Vector3d(s * s, s * s, s * s).asDiagonal();
  for (int k = 1; k <= 60; ++k) {
    const Pose2& m = marks[k % 3];
    Pose2 seen = relative(truth, m);
    seen = {seen.x + gaussian(rng, s), seen.y + gaussian(rng, s), wrap_angle(seen.a + gaussian(rng, s))};
    EXPECT_NE(f.add_landmark(0.01 * k, m, seen, cov), PoseEkf::Outcome::Invalid);
  }
  Eigen::Matrix3d pc = f.covariance().topLeftCorner<3, 3>();
  EXPECT_NEAR(f.pose().x, truth.x, 4 * std::sqrt(pc(0, 0)));
  EXPECT_NEAR(f.pose().y, truth.y, 4 * std::sqrt(pc(1, 1)));
  EXPECT_NEAR(f.pose().a, truth.a, 4 * std::sqrt(pc(2, 2)));
  EXPECT_LT(std::sqrt(pc(0, 0)), 0.03);
}

}  // namespace
}  // namespace troupe::desktop
