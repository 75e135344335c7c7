// ros2: the devices this driver uses, published as ROS 2 topics over DDS
// (Eclipse Cyclone DDS; no ROS installation), and ROS 2 commands sent back to
// them. Devices come from the node: local drivers, or a robot's through
// passthrough (`troupe ros2 HOST` builds such a node for every device of a
// node or simulator).
//
// Uses (one topic each, in the device's namespace, "r0" for robot r0):
//   position2d  nav_msgs/Odometry on odom, odom -> base_link on /tf;
//               geometry_msgs/Twist on cmd_vel -> velocity commands
//   ranger      sensor_msgs/LaserScan on scan (a scanning sensor), or one
//               sensor_msgs/Range per transducer on sonar (a ring)
//   power       sensor_msgs/BatteryState on battery
//   imu         sensor_msgs/Imu on imu
//   bumper      sensor_msgs/Range per segment on bumper (fixed-distance)
//   localize    geometry_msgs/PoseWithCovarianceStamped on amcl_pose;
//               initialpose -> the localizer's SetPose
//   map         nav_msgs/OccupancyGrid on map (latched), fetched once
//   simulation  rosgraph_msgs/Clock on /clock
// and, for all of them: the sensors' poses on /tf_static, each device's
// health on /diagnostics (stale when silent for stale_after), and the node
// in ros_discovery_info.
// Provides: one opaque device, the bridge's state as JSON text.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "drivers/mcl/map_fetch.h"
#include "drivers/ros2/convert.h"
#include "drivers/ros2/dds.h"
#include "drivers/ros2/graph.h"
#include "drivers/ros2/names.h"
#include "drivers/ros2/stamps.h"
#include "runtime/driver.h"
#include "runtime/node_config.h"

namespace troupe::drivers::ros2 {

class Ros2Bridge : public Driver {
 public:
  bool setup(Node& node, const DriverSetup& setup, std::string& error) override;
  void on_data(DeviceId source, const wire::Message& data) override;
  void on_reply(DeviceId device, const wire::Message& reply) override;
  void on_request(DeviceId device, const wire::Message& request, RequestToken token) override;
  void on_fd(int fd, uint32_t events) override;
  void on_timer(TimerId id) override;
  void shutdown() override;

  /// The state the opaque device reports (JSON, one object).
  std::string status_text() const;

 private:
  enum class Kind { Position, Ranger, Power, Inertial, Bumper, Localize, Map, Simulation };
  enum class RangerShape { Unknown, Scan, Array };
  /// A request the bridge sends a device once (geometry, config).
  struct Fetch {
    bool wanted = false;
    bool done = false;
    uint32_t seq = 0;       // of the request in flight, 0: none
    uint64_t retry_at = 0;  // loop time, us
  };
  struct Bridged {
    DeviceId id = kNoDevice;
    wire::Address addr{};
    Kind kind = Kind::Position;
    std::string label;                        // "r0/ranger:0"
    std::string ns;                           // "r0", or "" (the root)
    std::string topic;                        // "/r0/scan"
    std::string command_topic;                // "/r0/cmd_vel", "/r0/initialpose"
    std::string frame;                        // "r0/base_scan"; position2d: the base frame
    std::string frame_given;                  // ranger: the frames option's entry
    std::string odom_frame;                   // position2d: "r0/odom"
    std::vector<std::string> element_frames;  // "r0/sonar_3", "r0/bumper_1"
    dds_entity_t writer = 0;
    dds_entity_t reader = 0;
    bool tf = false;
    RangerShape shape = RangerShape::Unknown;
    Fetch geometry, config;
    // The sensor's pose and its transducers' (ranger), once geometry came.
    bool has_geometry = false;
    wire::Pose3d pose{};
    std::vector<wire::Pose3d> elements;
    float min_range = 0;      // m, from the config
    float field_of_view = 0;  // rad, from the config
    float scan_time = 0;      // s between scans, from the config
    mcl::MapFetch map;
    bool map_published = false;
    uint64_t map_retry_at = 0;  // loop time, us
    // Health.
    uint64_t samples = 0;
    uint64_t last_data_us = 0;  // loop time of the last sample, 0: none yet
    bool stale = false;
    uint32_t clamped = 0, refused = 0;
    std::string problem;  // the latest refusal or failure
  };

  bool add_device(DeviceId id, size_t use_index, const Options& opt, std::string& error);
  bool open_endpoints(Bridged& b, std::string& error);
  dds_entity_t writer(const std::string& ros_topic, const dds_topic_descriptor_t& desc, const QosProfile& qos,
                      std::string& error);
  Bridged* by_id(DeviceId id);
  /// The ROS stamp of a sample (its header's time), or of a device time, us.
  Time stamp_of(const Bridged& b, const wire::Message& msg);
  Time stamp_at(const Bridged& b, uint64_t device_us);
  Time ros_now() const;
  void write(Bridged& b, dds_entity_t w, const void* sample);

  /// A message filled from one body by `fill` (convert.h), if the body is there.
  template <typename Out, typename In>
  void publish_sensor(Bridged& b, const wire::Message& msg, const In* in,
                      void (*fill)(const In&, Time, const std::string&, Out&)) {
    if (in == nullptr) return;
    Out out;
    fill(*in, stamp_of(b, msg), b.frame, out);
    write(b, b.writer, &out);
  }
  void publish_position(Bridged& b, const wire::Message& msg);
  void publish_ranger(Bridged& b, const wire::Message& msg);
  void publish_bumper(Bridged& b, const wire::Message& msg);
  void publish_map(Bridged& b);
  void publish_static_tf();
  void publish_diagnostics();
  void publish_status();

  void send_requests();
  void send_fetch(Bridged& b, Fetch& f, uint8_t subtype);
  void on_geometry(Bridged& b, const wire::Message& reply);
  bool name_ranger(Bridged& b, const wire::RangerScan& scan);
  void ranger_static_tf(Bridged& b);
  void set_static_tf(const std::string& parent, const std::string& child, const Transform& t);

  void take_commands(Bridged& b);
  void take_initial_poses(Bridged& b);
  void check_health();

  std::string name_;
  Participant dds_;
  Graph graph_;
  std::unique_ptr<StampMap> stamps_;
  std::vector<Bridged> devices_;
  std::map<DeviceId, size_t> index_;
  DeviceId status_ = kNoDevice;
  TimerId tick_ = 0;
  uint32_t seq_ = 0;
  int in_flight_ = 0;
  bool sending_ = false;

  // Options.
  std::string base_frame_ = "base_link", odom_frame_ = "odom", map_frame_ = "map";
  VelLimits limits_;
  uint64_t stale_after_us_ = 3'000'000;
  uint32_t domain_ = 0;
  bool publish_tf_ = true;

  // Writers shared by every device.
  dds_entity_t tf_ = 0, tf_static_ = 0, clock_ = 0, diagnostics_ = 0;
  // Static transforms by child frame: parent and transform.
  std::map<std::string, std::pair<std::string, Transform>> static_tf_;
  bool static_tf_dirty_ = false;
  uint64_t latest_sim_us_ = 0;  // newest simulated time seen (sim mode)
  uint64_t start_us_ = 0;       // loop time at setup

  // Scratch storage the messages point into while they are written.
  std::vector<float> ranges_, intensities_;
  std::vector<int8_t> cells_;
  std::vector<std::string> strings_;
};

}  // namespace troupe::drivers::ros2
