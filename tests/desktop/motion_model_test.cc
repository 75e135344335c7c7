// The odometry motion model's statistics: samples have the mean and spread
// the model says, and a seed gives the same samples.
#include "drivers/common_desktop/motion_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "drivers/common_desktop/odometry_noise.h"

namespace troupe::desktop {
namespace {

struct Moments {
  double mean = 0, var = 0;
};

Moments moments(const std::vector<double>& v) {
  Moments m;
  for (double x : v) m.mean += x;
  m.mean /= double(v.size());
  for (double x : v) m.var += (x - m.mean) * (x - m.mean);
  m.var /= double(v.size() - 1);
  return m;
}

constexpr int kSamples = 40000;
// Sample variance of n normal draws has relative standard error sqrt(2/n)
// (0.7% here); 5% is more than six of those.
constexpr double kVarTolerance = 0.05;

TEST(MotionModel, DecomposeSplitsTurnMoveTurn) {
  OdometryMotion m = decompose({1, 1, 0}, {1, 3, kPi});
  EXPECT_NEAR(m.rot1, kPi / 2, 1e-12);
  EXPECT_NEAR(m.trans, 2, 1e-12);
  EXPECT_NEAR(m.rot2, kPi / 2, 1e-12);
  // On the spot: no first turn, all of it in the second.
  m = decompose({0, 0, 0.2}, {0, 0, -0.3});
  EXPECT_EQ(m.rot1, 0);
  EXPECT_NEAR(m.rot2, -0.5, 1e-12);
  // Backwards: rot1 near pi, but the noise sees a small turn.
  m = decompose({0, 0, 0}, {-1, 0, 0});
  EXPECT_NEAR(std::fabs(m.rot1), kPi, 1e-12);
  EXPECT_NEAR(noise_turn(m.rot1), 0, 1e-12);
}

TEST(MotionModel, StraightMoveSpreadsAsTheModelSays) {
  MotionNoise noise{0.0, 0.1, 0.05, 0.0};  // rot from trans, trans from trans only
  OdometryMotion m = decompose({0, 0, 0}, {2, 0, 0});
  Rng rng(42);
  std::vector<double> along, heading;
  for (int i = 0; i < kSamples; ++i) {
    Pose2 p = sample_motion(Pose2{}, m, noise, rng);
    along.push_back(std::hypot(p.x, p.y));
    heading.push_back(p.a);
  }
  // Distance: N(2, 0.05 * 2^2). Heading: two independent turns, each with
  // variance 0.1 * 2^2.
  Moments d = moments(along), a = moments(heading);
  EXPECT_NEAR(d.mean, 2.0, 4 * std::sqrt(0.2 / kSamples));
  EXPECT_NEAR(d.var / 0.2, 1.0, kVarTolerance);
  EXPECT_NEAR(a.mean, 0.0, 4 * std::sqrt(0.8 / kSamples));
  EXPECT_NEAR(a.var / 0.8, 1.0, kVarTolerance);
}

TEST(MotionModel, TurnOnTheSpotSpreadsWithTheTurn) {
  MotionNoise noise{0.2, 0.0, 0.0, 0.01};  // rot from rot, trans from rot
  OdometryMotion m = decompose({0, 0, 0}, {0, 0, 1.0});
  Rng rng(7);
  std::vector<double> heading, moved;
  for (int i = 0; i < kSamples; ++i) {
    Pose2 p = sample_motion(Pose2{}, m, noise, rng);
    heading.push_back(p.a);
    moved.push_back(p.x);  // rot1 = 0: any distance goes along x
  }
  Moments a = moments(heading), x = moments(moved);
  EXPECT_NEAR(a.mean, 1.0, 4 * std::sqrt(0.2 / kSamples));
  EXPECT_NEAR(a.var / 0.2, 1.0, kVarTolerance);   // only rot2 = 1 rad turns: 0.2 * 1^2
  EXPECT_NEAR(x.var / 0.01, 1.0, kVarTolerance);  // trans_rot * (0^2 + 1^2)
}

TEST(MotionModel, NoNoiseMeansExactMotionAndSeedsRepeat) {
  OdometryMotion m = decompose({1, 2, 0.3}, {2.5, 1.0, -1.0});
  Rng rng(1);
  Pose2 p = sample_motion({1, 2, 0.3}, m, MotionNoise{0, 0, 0, 0}, rng);
  EXPECT_NEAR(p.x, 2.5, 1e-12);
  EXPECT_NEAR(p.y, 1.0, 1e-12);
  EXPECT_NEAR(p.a, -1.0, 1e-12);
  Rng a(99), b(99), c(100);
  Pose2 pa = sample_motion({}, m, MotionNoise{}, a), pb = sample_motion({}, m, MotionNoise{}, b);
  Pose2 pc = sample_motion({}, m, MotionNoise{}, c);
  EXPECT_EQ(pa.x, pb.x);
  EXPECT_EQ(pa.a, pb.a);
  EXPECT_NE(pa.x, pc.x);
}

TEST(OdometryNoise, DriftScalesDistanceAndSlipOnlyAddsDistance) {
  OdometryNoise noise{};
  noise.scale_sigma = 0;
  noise.turn_bias_sigma = 0;
  noise.trans_per_m = 0;
  noise.rot_per_rad = 0;
  noise.rot_per_m = 0;
  noise.slip_probability = 0;
  Rng rng(3);
  OdometrySynthesizer exact(noise, rng);
  exact.next({0, 0, 0}, rng);
  Pose2 o = exact.next({3, 4, 0.5}, rng);
  EXPECT_NEAR(o.x, 3, 1e-12);
  EXPECT_NEAR(o.y, 4, 1e-12);
  EXPECT_NEAR(o.a, 0.5, 1e-12);

  noise.slip_probability = 1;
  noise.slip_max_extra = 0.5;
  OdometrySynthesizer slipping(noise, rng);
  slipping.next({0, 0, 0}, rng);
  double total = 0;
  Pose2 last{};
  for (int i = 1; i <= 1000; ++i) {
    Pose2 p = slipping.next({double(i), 0, 0}, rng);
    double step = p.x - last.x;
    EXPECT_GE(step, 1.0);
    EXPECT_LE(step, 1.5);
    total += step;
    last = p;
  }
  EXPECT_NEAR(total / 1000, 1.25, 0.03);  // uniform extra share: mean 0.25
}

}  // namespace
}  // namespace troupe::desktop
