// The fusion driver in a node: a source driver publishes odometry, gyro,
// fiducial sightings and late localize fixes of a simulated drive; fusion's
// position2d must follow the truth with a covariance that covers its error.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>

#include "drivers/common_desktop/pose2.h"
#include "drivers/common_desktop/rng.h"
#include "runtime/node_config.h"
#include "tests/desktop/synthetic_world.h"

namespace troupe {
namespace {

using desktop::Pose2;

// Serves the inputs (position2d:0, imu:0, fiducial:0, localize:0) and reads
// fusion's output (position2d:1).
class Source : public Driver {
 public:
  bool setup(Node& node, const DriverSetup&, std::string&) override {
    out_ = node.find_device(wire::Address(0, uint16_t(wire::Interface::Position2d), 1));
    node.subscribe(out_, this);
    return true;
  }
  void on_data(DeviceId, const wire::Message& m) override {
    const wire::Position2dState* s = m.body_as_Position2dState();
    if (s == nullptr || s->covariance() == nullptr) return;
    last = {s->pose()->x(), s->pose()->y(), s->pose()->a()};
    last_var_xx = s->covariance()->xx();
    last_time_us = wire::time_us(*m.header());
    ++outputs;
  }
  Pose2 last;
  double last_var_xx = 0;
  uint64_t last_time_us = 0;
  size_t outputs = 0;

 private:
  DeviceId out_ = kNoDevice;
};

// A localizer's best hypothesis at `p`, its covariance small, stamped `t_us`.
void publish_fix(Node& node, DeviceId loc, uint64_t t_us, const Pose2& p, bool lost = false) {
  auto& b = node.begin();
  wire::Hypothesis h(wire::Pose2d(float(p.x), float(p.y), float(p.a)), wire::Cov2d(0.01f, 0, 0, 0.01f, 0, 0.003f),
                     1.0f);
  auto body = wire::CreateLocalizeState(b, b.CreateVectorOfStructs(&h, 1), 0, 0, lost);
  node.publish(loc, uint8_t(wire::LocalizeDataSub::Hypotheses), wire::Body::LocalizeState, body.Union(), t_us);
}

void publish_odometry(Node& node, DeviceId odom, uint64_t t_us, const Pose2& p) {
  auto& b = node.begin();
  wire::Pose2d pose(float(p.x), float(p.y), float(p.a));
  auto body = wire::CreatePosition2dState(b, &pose);
  node.publish(odom, uint8_t(wire::Position2dDataSub::State), wire::Body::Position2dState, body.Union(), t_us);
}

// A node running the config `json`, with a Source serving the inputs
// (INTERFACE:0 each) and reading fusion's output.
class FusionDriver : public ::testing::Test {
 protected:
  void start(const std::string& json, std::initializer_list<wire::Interface> inputs) {
    const std::string dir = desktop::testing::scratch_dir();
    std::ofstream(dir + "/fusion.json") << json;
    std::string error;
    ASSERT_TRUE(load_config(dir + "/fusion.json", cfg_, error)) << error;
    node_ = std::make_unique<Node>(node_options(*cfg_.root));
    auto owned = std::make_unique<Source>();
    src_ = owned.get();
    // The source's devices exist before the config's instances resolve "uses".
    for (wire::Interface i : inputs) in_[i] = node_->add_device(wire::Address(0, uint16_t(i), 0), src_, "source");
    ASSERT_TRUE(build_node(*node_, cfg_, error)) << error;
    ASSERT_TRUE(node_->add_driver(std::move(owned), {}, error)) << error;
  }

  LoadedConfig cfg_;
  std::unique_ptr<Node> node_;
  Source* src_ = nullptr;  // owned by node_
  std::map<wire::Interface, DeviceId> in_;
};

TEST_F(FusionDriver, FusesOdometryGyroFiducialsAndLateFixes) {
  start(R"({ "port": 0, "drivers": [
    { "driver_type": "fusion",
      "driver": { "gyro_sigma": 0.01, "odom_speed_sigma": 0.05, "odom_turn_sigma": 0.05,
                  "landmarks": [ { "id": 7, "x": 5.0, "y": 0.0, "a": 3.14159 },
                                 { "id": 9, "x": 0.0, "y": 5.0, "a": -1.5708 } ] },
      "uses": ["position2d:0", "imu:0", "fiducial:0", "localize:0"],
      "provides": ["position2d:1"] } ] })",
        {wire::Interface::Position2d, wire::Interface::Imu, wire::Interface::Fiducial, wire::Interface::Localize});
  if (HasFatalFailure()) return;
  Node& node = *node_;
  Source& src = *src_;
  const DeviceId odom = in_[wire::Interface::Position2d], imu = in_[wire::Interface::Imu],
                 fid = in_[wire::Interface::Fiducial], loc = in_[wire::Interface::Localize];

  desktop::Rng rng(17);
  const uint64_t t0 = 1'000'000'000;
  auto fix = [&](uint64_t t, const Pose2& p) { publish_fix(node, loc, t, p); };
  // The first fix starts the filter at the true start.
  Pose2 truth{0, 0, 0}, odo{3, -2, 1};  // odometry has its own frame
  fix(t0, truth);
  std::map<uint64_t, Pose2> truths;
  double max_err = 0, max_z = 0;
  const double v = 0.5, dt = 0.05;
  for (int k = 1; k <= 400; ++k) {
    uint64_t t = t0 + uint64_t(k) * 50'000;
    double w = 0.3 * std::sin(k * 0.02);
    truth = desktop::compose(truth, {v * dt, 0, w * dt});
    truths[t] = truth;
    // Odometry: the same motion, 5% long; the gyro: the true rate.
    odo = desktop::compose(odo, {1.05 * v * dt, 0, (w + desktop::gaussian(rng, 0.02)) * dt});
    publish_odometry(node, odom, t, odo);
    {
      auto& b = node.begin();
      wire::Vec3 gyro(0, 0, float(w + desktop::gaussian(rng, 0.01)));
      auto body = wire::CreateImuState(b, &gyro);
      node.publish(imu, uint8_t(wire::ImuDataSub::State), wire::Body::ImuState, body.Union(), t);
    }
    if (k % 10 == 0) {  // a landmark sighting, and an unknown id that is ignored
      const Pose2 mark = k % 20 ? Pose2{5.0, 0.0, 3.14159} : Pose2{0.0, 5.0, -1.5708};
      Pose2 seen = desktop::relative(truth, mark);
      wire::Fiducial f[2] = {wire::Fiducial(k % 20 ? 7 : 9, float(seen.x + desktop::gaussian(rng, 0.05)),
                                            float(seen.y + desktop::gaussian(rng, 0.05)), float(seen.a)),
                             wire::Fiducial(42, 1, 1, 0)};
      auto& b = node.begin();
      auto body = wire::CreateFiducialList(b, b.CreateVectorOfStructs(f, 2));
      node.publish(fid, uint8_t(wire::FiducialDataSub::Detections), wire::Body::FiducialList, body.Union(),
                   t);
    }
    if (k % 25 == 0) {  // a fix of 0.3 s ago: arrives late, applied in the past
      uint64_t then = t - 300'000;
      Pose2 p = truths[then];
      fix(then, {p.x + desktop::gaussian(rng, 0.1), p.y + desktop::gaussian(rng, 0.1), p.a});
    }
    ASSERT_EQ(src.last_time_us, t) << "fusion publishes after each odometry sample";
    double err = desktop::distance(src.last, truth);
    max_err = std::max(max_err, err);
    if (k > 20) max_z = std::max(max_z, err / std::sqrt(src.last_var_xx * 2));
  }
  EXPECT_GT(src.outputs, 400u);
  // Dead reckoning alone would be 5% of 10 m = 0.5 m off by the end.
  EXPECT_LT(desktop::distance(src.last, truth), 0.15);
  EXPECT_LT(max_err, 0.3);
  EXPECT_LT(max_z, 5.0) << "the reported covariance must cover the error";
}

// mcl says when it is lost (its scans fit far worse than they did) and
// keeps publishing its best guess while it searches. Fusion must not follow
// that guess, not even after max_gated refusals, and must follow the
// localizer again once it has found itself, wherever that is.
TEST_F(FusionDriver, IgnoresTheFixesOfALocalizerThatSaysItIsLost) {
  start(R"({ "port": 0, "drivers": [
    { "driver_type": "fusion", "driver": { "max_gated": 3 },
      "uses": ["position2d:0", "localize:0"], "provides": ["position2d:1"] } ] })",
        {wire::Interface::Position2d, wire::Interface::Localize});
  if (HasFatalFailure()) return;
  Node& node = *node_;
  Source& src = *src_;
  const DeviceId odom = in_[wire::Interface::Position2d], loc = in_[wire::Interface::Localize];

  // The robot stands at the origin; odometry says so at 10 Hz.
  uint64_t t = 1'000'000'000;
  auto tick = [&] {
    t += 100'000;
    publish_odometry(node, odom, t, {0, 0, 0});
  };
  publish_fix(node, loc, t, {0, 0, 0});
  for (int k = 0; k < 5; ++k) tick();
  ASSERT_LT(desktop::distance(src.last, {0, 0, 0}), 0.01);

  // Lost: its guesses, near (the gate would pass them) and far (max_gated
  // refusals would make the filter jump there), move nothing.
  for (int k = 0; k < 10; ++k) {
    publish_fix(node, loc, t, k % 2 ? Pose2{0.4, 0, 0} : Pose2{3, 3, 1}, true);
    tick();
  }
  EXPECT_LT(desktop::distance(src.last, {0, 0, 0}), 0.01) << "followed a lost localizer";

  // Found again, at a pose the robot was carried to (kidnapped): the
  // filter refuses max_gated fixes, then believes the localizer.
  for (int k = 0; k < 6; ++k) {
    publish_fix(node, loc, t, {3, 3, 1});
    tick();
  }
  EXPECT_LT(desktop::distance(src.last, {3, 3, 1}), 0.05) << "did not follow the recovered localizer";
}

}  // namespace
}  // namespace troupe
