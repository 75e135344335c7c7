// mcl: adaptive Monte Carlo localization as a device. Reads odometry, laser
// scans and a map from other devices of the node; serves the belief as
// localize hypotheses and the best estimate as a position2d in the map frame.
// The algorithm is desktop::ParticleFilter; this driver only feeds it.
//
// Uses: position2d (odometry), ranger (a scanning laser), map (fetched once
// at start, tile by tile). Or, for feature-based localization (option
// landmark_table): position2d, fiducial (landmark detections) and
// optionally a map.
// Provides: localize (required), position2d (optional).
// Requests: localize SetPose (pose tracking from a pose and covariance),
// Global (global localization).
//
// Odometry and scans are paired by timestamp: the odometry pose at a scan's
// time is interpolated from the odometry around it. A scan newer than every
// odometry sample waits up to odom_wait for odometry to pass it. Odometry
// whose clock goes back, or whose pose jumps back to its origin or faster
// than the robot can move, restarted: the jump is not taken as motion.
#pragma once

#include <memory>

#include "drivers/common_desktop/landmark_model.h"
#include "drivers/common_desktop/particle_filter.h"
#include "drivers/mcl/map_fetch.h"
#include "runtime/driver.h"
#include "runtime/node_config.h"

namespace troupe::drivers::mcl {

class Mcl : public Driver {
 public:
  bool setup(Node& node, const DriverSetup& setup, std::string& error) override;
  void on_data(DeviceId source, const wire::Message& data) override;
  void on_request(DeviceId device, const wire::Message& request, RequestToken token) override;
  void on_reply(DeviceId device, const wire::Message& reply) override;
  void on_timer(TimerId id) override;

  /// The filter, once the map has arrived (nullptr before).
  const desktop::ParticleFilter* filter() const { return filter_.get(); }

 private:
  struct OdomSample {
    uint64_t time_us;
    desktop::Pose2 pose;
  };
  enum class Init : uint8_t { Global, Pose };

  void on_odometry(const wire::Message& data);
  void on_scan(const wire::Message& data);
  void on_landmarks(const wire::Message& data);
  void measured(uint64_t time_us);
  bool odometry_at(uint64_t time_us, desktop::Pose2& out) const;
  void process_pending_scan(bool force);
  void start_filter(desktop::OccupancyGrid map);
  bool setup_landmarks(const OptionsView<Options>& options, std::string& error);
  void apply_init();
  void publish(uint64_t time_us);

  desktop::MclParams params_;
  std::string name_;
  DeviceId odom_in_ = kNoDevice, scan_in_ = kNoDevice, map_in_ = kNoDevice, landmarks_in_ = kNoDevice;
  DeviceId localize_ = kNoDevice, position_ = kNoDevice;
  MapFetch fetch_;
  desktop::OccupancyGrid map_;
  std::unique_ptr<desktop::ParticleFilter> filter_;
  desktop::Rng rng_;
  Init init_ = Init::Global;
  desktop::Pose2 init_pose_;
  Eigen::Matrix3d init_cov_ = Eigen::Matrix3d::Zero();
  TimerId fetch_timer_ = 0;
  TimerId wait_timer_ = 0;
  uint64_t odom_wait_us_ = 0;
  double odom_max_speed_ = 0, odom_max_turn_rate_ = 0;  // m/s, rad/s
  bool said_lost_ = false;                              // the lost state last logged
  // Newest odometry first-in-first-out, enough for a few seconds.
  static constexpr size_t kOdomHistory = 256;
  std::vector<OdomSample> odom_;
  size_t odom_head_ = 0;  // next slot to write
  size_t odom_count_ = 0;
  float odom_v_ = 0, odom_w_ = 0;
  // The newest scan waiting for odometry (one: an older waiting scan is
  // replaced, like a newer command replaces an older one).
  bool scan_pending_ = false;
  uint64_t scan_time_us_ = 0;
  desktop::ScanView scan_view_;
  std::vector<float> scan_ranges_;
  std::vector<wire::Hypothesis> hyp_out_;  // reused for each publication
  size_t bad_scans_ = 0;
  // Feature-based localization: the table, the model over it, and the
  // detections waiting for odometry (pending_landmarks_: the pending
  // measurement is these rather than a scan).
  desktop::LandmarkTable table_;
  std::unique_ptr<desktop::LandmarkLikelihood> landmark_model_;
  std::vector<desktop::LandmarkObservation> seen_;
  bool pending_landmarks_ = false;
};

}  // namespace troupe::drivers::mcl
