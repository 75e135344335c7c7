// logreplay: plays a CARMEN log (ODOM, FLASER, ROBOTLASER1, TRUEPOS) as
// devices, at the recorded pace or a multiple of it, so that localization
// and mapping run on real recorded data exactly as on a robot.
//
// Provides: position2d (odometry), ranger (the laser), and optionally a
// second position2d with the ground truth: TRUEPOS lines, or the scans' poses
// of a SLAM-corrected log. Each sample is stamped with the node time at which
// it is due: start + (log time - first log time) / speed.
// Requests: position2d and ranger Geometry (the laser at the robot's
// centre), ranger GetConfig. Nothing can be commanded.
#pragma once

#include "drivers/common_desktop/replay_timeline.h"
#include "runtime/driver.h"
#include "runtime/node_config.h"

namespace troupe::drivers::logreplay {

class LogReplay : public Driver {
 public:
  bool setup(Node& node, const DriverSetup& setup, std::string& error) override;
  void on_request(DeviceId device, const wire::Message& request, RequestToken token) override;
  void on_timer(TimerId id) override;

  /// Samples played so far (this pass of the log).
  size_t played() const { return next_; }

 private:
  void schedule();
  void publish(const desktop::ReplaySample& s, uint64_t time_us);
  uint64_t due_us(size_t i) const;

  desktop::CarmenLog log_;
  desktop::Timeline timeline_;
  DeviceId odom_ = kNoDevice, ranger_ = kNoDevice, truth_ = kNoDevice;
  double speed_ = 1;
  bool loop_ = false;
  uint64_t start_us_ = 0;
  size_t next_ = 0;
  std::vector<uint16_t> ranges_;  // scratch for one scan
};

}  // namespace troupe::drivers::logreplay
