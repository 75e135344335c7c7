// Troupe data into ROS 2 messages and ROS 2 commands into Troupe commands:
// pure functions on the generated message structs (drivers/ros2/msg, IDL by
// idlc), no DDS and no node, so tests run them on their own.
//
// Strings and sequences in the filled structs point into the caller's
// buffers (frame names, scratch vectors): keep those alive until the message
// is written.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "drivers/common_desktop/occupancy_grid.h"
#include "drivers/ros2/ros2_msgs.h"
#include "wire/message.h"

namespace troupe::drivers::ros2 {

using Time = builtin_interfaces_msg_dds__Time_;
using Quaternion = geometry_msgs_msg_dds__Quaternion_;
using Twist = geometry_msgs_msg_dds__Twist_;
using Transform = geometry_msgs_msg_dds__Transform_;
using TransformStamped = geometry_msgs_msg_dds__TransformStamped_;
using PoseWithCovarianceStamped = geometry_msgs_msg_dds__PoseWithCovarianceStamped_;
using Odometry = nav_msgs_msg_dds__Odometry_;
using OccupancyGrid = nav_msgs_msg_dds__OccupancyGrid_;
using LaserScan = sensor_msgs_msg_dds__LaserScan_;
using Range = sensor_msgs_msg_dds__Range_;
using BatteryState = sensor_msgs_msg_dds__BatteryState_;
using Imu = sensor_msgs_msg_dds__Imu_;
using TFMessage = tf2_msgs_msg_dds__TFMessage_;
using Clock = rosgraph_msgs_msg_dds__Clock_;
using DiagnosticArray = diagnostic_msgs_msg_dds__DiagnosticArray_;
using DiagnosticStatus = diagnostic_msgs_msg_dds__DiagnosticStatus_;
using KeyValue = diagnostic_msgs_msg_dds__KeyValue_;

/// ROS time from microseconds since the clock's epoch.
Time ros_time(uint64_t us);
/// The rotation of roll, pitch, yaw (rad; applied yaw, then pitch, then roll).
Quaternion quaternion_from_rpy(double roll, double pitch, double yaw);
/// The heading (rad) of a rotation about the vertical.
double yaw_of(const Quaternion& q);

/// A planar covariance (x, y, heading) into ROS's row-major 6x6 over (x, y,
/// z, roll, pitch, yaw), the rest zero.
void covariance_6x6(const wire::Cov2d& c, double out[36]);
/// The planar part of a ROS 6x6 covariance.
wire::Cov2d covariance_2d(const double in[36]);

/// A pose on the robot as the transform from the robot's frame.
Transform transform_of(const wire::Pose3d& pose);

/// Odometry: pose in `odom_frame`, velocity in `base_frame` (the robot's).
void fill_odometry(const wire::Position2dState& state, Time stamp, const std::string& odom_frame,
                   const std::string& base_frame, Odometry& out);
/// The odom -> base transform an odometry message states.
void fill_odom_transform(const Odometry& odom, TransformStamped& out);

/// True for a scanning sensor (one origin, evenly spaced beams): a
/// LaserScan. Transducer arrays (sonar rings) leave angular_res 0.
bool is_scan(const wire::RangerScan& scan);
/// Range i of a scan, m; +Inf where the beam had no return.
float range_at(const wire::RangerScan& scan, size_t i);
/// A laser scan. `range_min` (m) and `scan_time` (s between scans) come
/// from elsewhere (the device's config, the stamps); `ranges` and
/// `intensities` are the message's storage.
void fill_laser_scan(const wire::RangerScan& scan, Time stamp, const std::string& frame, float range_min,
                     float scan_time, std::vector<float>& ranges, std::vector<float>& intensities,
                     LaserScan& out);
/// Transducer i of an array (a sonar ring), as ROS drivers publish one
/// sonar: field of view and minimum range (rad, m) from the device's config.
void fill_sonar_range(const wire::RangerScan& scan, size_t i, Time stamp, const std::string& frame,
                      float field_of_view, float min_range, Range& out);
/// One bumper segment as a fixed-distance detector (min_range == max_range
/// == 0): -Inf while pressed, +Inf while not.
void fill_bumper_range(bool pressed, Time stamp, const std::string& frame, Range& out);

/// Only what the device measured; the rest NaN (BatteryState's "unknown").
void fill_battery(const wire::PowerState& power, Time stamp, const std::string& frame, BatteryState& out);
/// Quantities the device did not measure have covariance element 0 at -1.
void fill_imu(const wire::ImuState& imu, Time stamp, const std::string& frame, Imu& out);
/// The best hypothesis, as amcl publishes amcl_pose. False when there is none.
bool fill_amcl_pose(const wire::LocalizeState& state, Time stamp, const std::string& map_frame,
                    PoseWithCovarianceStamped& out);
/// The grid (0 free, 100 occupied, -1 unknown); `cells` is the storage.
void fill_occupancy_grid(const desktop::OccupancyGrid& grid, Time stamp, const std::string& map_frame,
                         std::vector<int8_t>& cells, OccupancyGrid& out);

/// What became of a command from ROS.
enum class Verdict {
  Ok,
  /// changed to fit the limits, then sent
  Clamped,
  /// not sent: a value is not a number or infinite
  Refused,
};

/// Speed limits for cmd_vel: m/s along x and y, rad/s about z.
struct VelLimits {
  double linear = 1.5;
  double angular = 3.0;
};

/// cmd_vel into a position2d velocity (robot frame: m/s, m/s, rad/s). A
/// planar base has no use for linear.z, angular.x and angular.y: they are
/// ignored when finite. `why` says what was clamped or refused.
Verdict vel_from_twist(const Twist& twist, const VelLimits& limits, wire::Pose2d& vel, std::string& why);

/// initialpose into a localize SetPose (map frame: m, m, rad and the planar
/// covariance). False with `why` for a non-finite or negative-variance pose.
bool pose_from_initialpose(const PoseWithCovarianceStamped& msg, wire::Pose2d& mean, wire::Cov2d& cov,
                           std::string& why);

}  // namespace troupe::drivers::ros2
