#include "drivers/ros2/convert.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace troupe::drivers::ros2 {

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// The generated structs hold char* where ROS has strings; they only read them.
char* text(const std::string& s) {
  return const_cast<char*>(s.c_str());
}

template <typename Seq, typename T>
void point_at(Seq& seq, std::vector<T>& storage) {
  seq._maximum = seq._length = uint32_t(storage.size());
  seq._buffer = storage.data();
  seq._release = false;
}

void header(std_msgs_msg_dds__Header_& h, Time stamp, const std::string& frame) {
  h.stamp = stamp;
  h.frame_id = text(frame);
}

}  // namespace

Time ros_time(uint64_t us) {
  Time t;
  t.sec = int32_t(us / 1'000'000u);
  t.nanosec = uint32_t(us % 1'000'000u) * 1000u;
  return t;
}

Quaternion quaternion_from_rpy(double roll, double pitch, double yaw) {
  const double cr = std::cos(roll / 2), sr = std::sin(roll / 2);
  const double cp = std::cos(pitch / 2), sp = std::sin(pitch / 2);
  const double cy = std::cos(yaw / 2), sy = std::sin(yaw / 2);
  Quaternion q;
  q.w = cr * cp * cy + sr * sp * sy;
  q.x = sr * cp * cy - cr * sp * sy;
  q.y = cr * sp * cy + sr * cp * sy;
  q.z = cr * cp * sy - sr * sp * cy;
  return q;
}

double yaw_of(const Quaternion& q) {
  return std::atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z));
}

void covariance_6x6(const wire::Cov2d& c, double out[36]) {
  std::fill(out, out + 36, 0.0);
  // Indices of x, y and yaw in the 6x6.
  constexpr int kX = 0, kY = 1, kA = 5;
  auto set = [&](int r, int col, double v) {
    out[r * 6 + col] = v;
    out[col * 6 + r] = v;
  };
  set(kX, kX, c.xx());
  set(kX, kY, c.xy());
  set(kX, kA, c.xa());
  set(kY, kY, c.yy());
  set(kY, kA, c.ya());
  set(kA, kA, c.aa());
}

wire::Cov2d covariance_2d(const double in[36]) {
  return wire::Cov2d(float(in[0]), float(in[1]), float(in[5]), float(in[7]), float(in[11]), float(in[35]));
}

Transform transform_of(const wire::Pose3d& pose) {
  Transform t;
  t.translation = {pose.x(), pose.y(), pose.z()};
  t.rotation = quaternion_from_rpy(pose.roll(), pose.pitch(), pose.yaw());
  return t;
}

void fill_odometry(const wire::Position2dState& state, Time stamp, const std::string& odom_frame,
                   const std::string& base_frame, Odometry& out) {
  out = Odometry{};
  header(out.header, stamp, odom_frame);
  out.child_frame_id = text(base_frame);
  if (const wire::Pose2d* p = state.pose()) {
    out.pose.pose.position = {p->x(), p->y(), 0.0};
    out.pose.pose.orientation = quaternion_from_rpy(0, 0, p->a());
  } else {
    out.pose.pose.orientation.w = 1;
  }
  if (const wire::Cov2d* c = state.covariance()) covariance_6x6(*c, out.pose.covariance);
  if (const wire::Pose2d* v = state.vel()) {
    out.twist.twist.linear = {v->x(), v->y(), 0.0};
    out.twist.twist.angular = {0.0, 0.0, v->a()};
  }
}

void fill_odom_transform(const Odometry& odom, TransformStamped& out) {
  out = TransformStamped{};
  out.header = odom.header;
  out.child_frame_id = odom.child_frame_id;
  const auto& p = odom.pose.pose;
  out.transform.translation = {p.position.x, p.position.y, p.position.z};
  out.transform.rotation = p.orientation;
}

bool is_scan(const wire::RangerScan& scan) {
  return scan.angular_res() != 0 && scan.ranges() != nullptr && scan.ranges()->size() > 1;
}

float range_at(const wire::RangerScan& scan, size_t i) {
  const float r = float(scan.ranges()->Get(flatbuffers::uoffset_t(i))) * scan.scale();
  return scan.max_range() > 0 && r >= scan.max_range() ? kInf : r;
}

void fill_laser_scan(const wire::RangerScan& scan, Time stamp, const std::string& frame, float range_min,
                     float scan_time, std::vector<float>& ranges, std::vector<float>& intensities,
                     LaserScan& out) {
  out = LaserScan{};
  header(out.header, stamp, frame);
  const size_t n = scan.ranges() ? scan.ranges()->size() : 0;
  out.angle_min = scan.min_angle();
  out.angle_increment = scan.angular_res();
  out.angle_max = scan.min_angle() + float(n > 0 ? n - 1 : 0) * scan.angular_res();
  out.scan_time = scan_time;
  out.range_min = range_min;
  out.range_max = scan.max_range();
  ranges.resize(n);
  for (size_t i = 0; i < n; ++i) ranges[i] = range_at(scan, i);
  intensities.clear();
  if (scan.intensities() != nullptr && scan.intensities()->size() == n) {
    intensities.assign(scan.intensities()->begin(), scan.intensities()->end());
  }
  point_at(out.ranges, ranges);
  point_at(out.intensities, intensities);
}

void fill_sonar_range(const wire::RangerScan& scan, size_t i, Time stamp, const std::string& frame,
                      float field_of_view, float min_range, Range& out) {
  out = Range{};
  header(out.header, stamp, frame);
  out.radiation_type = sensor_msgs_msg_dds__Range_Constants_ULTRASOUND;
  out.field_of_view = field_of_view;
  out.min_range = min_range;
  out.max_range = scan.max_range();
  out.range = range_at(scan, i);
}

void fill_bumper_range(bool pressed, Time stamp, const std::string& frame, Range& out) {
  out = Range{};
  header(out.header, stamp, frame);
  // A contact switch: radiation_type (0) means nothing here.
  out.range = pressed ? -kInf : kInf;
}

void fill_battery(const wire::PowerState& power, Time stamp, const std::string& frame, BatteryState& out) {
  out = BatteryState{};
  header(out.header, stamp, frame);
  const auto volts = power.volts();
  const auto watts = power.watts();
  const auto joules = power.joules();
  out.voltage = volts ? *volts : kNaN;
  out.temperature = kNaN;
  // BatteryState's current is negative while discharging; Troupe's watts
  // are positive while drawing.
  out.current = volts && watts && *volts > 0 ? -*watts / *volts : kNaN;
  out.charge = volts && joules && *volts > 0 ? *joules / (*volts * 3600.0f) : kNaN;
  out.capacity = kNaN;
  out.design_capacity = kNaN;
  out.percentage = power.percent() ? *power.percent() / 100.0f : kNaN;
  if (const auto charging = power.charging()) {
    out.power_supply_status =
        *charging ? sensor_msgs_msg_dds__BatteryState_Constants_POWER_SUPPLY_STATUS_CHARGING
                  : sensor_msgs_msg_dds__BatteryState_Constants_POWER_SUPPLY_STATUS_DISCHARGING;
  } else {
    out.power_supply_status = sensor_msgs_msg_dds__BatteryState_Constants_POWER_SUPPLY_STATUS_UNKNOWN;
  }
  out.present = true;
  static const std::string kEmpty;
  out.location = text(kEmpty);
  out.serial_number = text(kEmpty);
}

void fill_imu(const wire::ImuState& imu, Time stamp, const std::string& frame, Imu& out) {
  out = Imu{};
  header(out.header, stamp, frame);
  if (const wire::Vec3* o = imu.orientation()) {
    out.orientation = quaternion_from_rpy(o->x(), o->y(), o->z());
  } else {
    out.orientation.w = 1;
    out.orientation_covariance[0] = -1;
  }
  if (const wire::Vec3* g = imu.gyro()) {
    out.angular_velocity = {g->x(), g->y(), g->z()};
  } else {
    out.angular_velocity_covariance[0] = -1;
  }
  if (const wire::Vec3* a = imu.accel()) {
    out.linear_acceleration = {a->x(), a->y(), a->z()};
  } else {
    out.linear_acceleration_covariance[0] = -1;
  }
}

bool fill_amcl_pose(const wire::LocalizeState& state, Time stamp, const std::string& map_frame,
                    PoseWithCovarianceStamped& out) {
  if (state.hypotheses() == nullptr || state.hypotheses()->size() == 0) return false;
  const wire::Hypothesis* best = state.hypotheses()->Get(0);
  out = PoseWithCovarianceStamped{};
  header(out.header, stamp, map_frame);
  out.pose.pose.position = {best->mean().x(), best->mean().y(), 0.0};
  out.pose.pose.orientation = quaternion_from_rpy(0, 0, best->mean().a());
  covariance_6x6(best->cov(), out.pose.covariance);
  return true;
}

void fill_occupancy_grid(const desktop::OccupancyGrid& grid, Time stamp, const std::string& map_frame,
                         std::vector<int8_t>& cells, OccupancyGrid& out) {
  out = OccupancyGrid{};
  header(out.header, stamp, map_frame);
  out.info.map_load_time = stamp;
  out.info.resolution = float(grid.resolution());
  out.info.width = grid.width();
  out.info.height = grid.height();
  out.info.origin.position = {grid.origin().x, grid.origin().y, 0.0};
  out.info.origin.orientation = quaternion_from_rpy(0, 0, grid.origin().a);
  // Both are row-major from cell (0, 0) at the origin.
  cells.resize(grid.cells().size());
  for (size_t i = 0; i < cells.size(); ++i) {
    switch (desktop::CellState(grid.cells()[i])) {
      case desktop::CellState::Free:
        cells[i] = 0;
        break;
      case desktop::CellState::Occupied:
        cells[i] = 100;
        break;
      default:
        cells[i] = -1;
        break;
    }
  }
  point_at(out.data, cells);
}

Verdict vel_from_twist(const Twist& twist, const VelLimits& limits, wire::Pose2d& vel, std::string& why) {
  const double all[6] = {twist.linear.x,  twist.linear.y,  twist.linear.z,
                         twist.angular.x, twist.angular.y, twist.angular.z};
  for (double v : all) {
    if (!std::isfinite(v)) {
      why = "cmd_vel holds a value that is not a finite number";
      return Verdict::Refused;
    }
  }
  Verdict verdict = Verdict::Ok;
  auto clamp = [&](double v, double limit, const char* name) {
    if (std::fabs(v) <= limit) return v;
    why = std::string("cmd_vel ") + name + " " + std::to_string(v) + " clamped to +-" + std::to_string(limit);
    verdict = Verdict::Clamped;
    return std::copysign(limit, v);
  };
  const double x = clamp(twist.linear.x, limits.linear, "linear.x");
  const double y = clamp(twist.linear.y, limits.linear, "linear.y");
  const double a = clamp(twist.angular.z, limits.angular, "angular.z");
  vel = wire::Pose2d(float(x), float(y), float(a));
  return verdict;
}

bool pose_from_initialpose(const PoseWithCovarianceStamped& msg, wire::Pose2d& mean, wire::Cov2d& cov,
                           std::string& why) {
  const auto& p = msg.pose.pose;
  const double values[7] = {p.position.x,    p.position.y,    p.position.z,   p.orientation.x,
                            p.orientation.y, p.orientation.z, p.orientation.w};
  for (double v : values) {
    if (!std::isfinite(v)) {
      why = "initialpose holds a pose that is not finite";
      return false;
    }
  }
  for (double v : msg.pose.covariance) {
    if (!std::isfinite(v)) {
      why = "initialpose holds a covariance that is not finite";
      return false;
    }
  }
  cov = covariance_2d(msg.pose.covariance);
  if (cov.xx() < 0 || cov.yy() < 0 || cov.aa() < 0) {
    why = "initialpose has a negative variance";
    return false;
  }
  mean = wire::Pose2d(float(p.position.x), float(p.position.y), float(yaw_of(p.orientation)));
  return true;
}

}  // namespace troupe::drivers::ros2
