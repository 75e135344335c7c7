// fusion: an EKF (desktop::PoseEkf) over odometry, a gyro's yaw rate and
// absolute fixes, served as one position2d with covariance.
//
// Uses: position2d (odometry, required); optionally imu (gyro z), localize
// (the best hypothesis as a fix), fiducial (sightings of the landmarks
// listed in the options).
// Provides: position2d (map frame; published after each odometry sample and
// each accepted fix).
//
// Every input is applied at its own timestamp: a fix that arrives after
// later odometry (a localizer is slow) is inserted in the past and the
// filter re-runs from there.
#pragma once

#include <unordered_map>

#include "drivers/common_desktop/ekf.h"
#include "runtime/driver.h"
#include "runtime/node_config.h"

namespace troupe::drivers::fusion {

class Fusion : public Driver {
 public:
  bool setup(Node& node, const DriverSetup& setup, std::string& error) override;
  void on_data(DeviceId source, const wire::Message& data) override;

  const desktop::PoseEkf& filter() const { return *ekf_; }

 private:
  void on_outcome(desktop::PoseEkf::Outcome o, const char* what);
  /// Publishes the state at `time_s` (s, node clock) or the filter's newest
  /// time, whichever is later.
  void publish(double time_s);

  std::string name_;
  DeviceId odom_in_ = kNoDevice, imu_in_ = kNoDevice, localize_in_ = kNoDevice, fiducial_in_ = kNoDevice;
  DeviceId out_ = kNoDevice;
  std::unique_ptr<desktop::PoseEkf> ekf_;
  double gyro_sigma_ = 0;
  double fix_min_var_xy_ = 0, fix_min_var_a_ = 0;
  double fid_sigma_xy_ = 0, fid_sigma_a_ = 0;
  std::unordered_map<int32_t, desktop::Pose2> landmarks_;
  float v_ = 0, w_ = 0;
  size_t warned_ = 0;
  bool localizer_lost_ = false;  // the last localize sample said "lost"
};

}  // namespace troupe::drivers::fusion
