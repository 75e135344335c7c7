// Eclipse Cyclone DDS as the bridge uses it: one domain participant carrying
// what ROS 2 expects of a participant (its user data), writers and readers on
// ROS 2 topic names with the QoS profiles ROS 2 drivers use, each endpoint's
// type hash in its user data (ROS 2 Iron and later), and readers that wake the
// node's event loop through a descriptor instead of calling into it.
//
// Cyclone receives on threads of its own; nothing here calls the node from
// them: a reader's listener only makes wake_fd() readable, and the node's one
// thread takes the samples (take()) when its loop sees the descriptor.
#pragma once

#include <dds/dds.h>

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>

namespace troupe::drivers::ros2 {

/// A QoS profile as ROS 2 states one.
struct QosProfile {
  bool reliable = true;
  /// Late joiners get the last `depth` samples (a "latched" topic).
  bool transient_local = false;
  /// Samples kept per writer (and reader), keep-last.
  int32_t depth = 10;
};
/// rclcpp's SensorDataQoS: best effort, the newest 5 (lasers, sonars, IMUs).
inline constexpr QosProfile kSensorDataQos{false, false, 5};
/// What ROS 2 drivers use by default (odometry, batteries, cmd_vel): reliable, 10.
inline constexpr QosProfile kDefaultQos{true, false, 10};
/// Latched: reliable, transient local, the newest 1 (map_server's /map,
/// amcl_pose, /tf_static, ros_discovery_info).
inline constexpr QosProfile kLatchedQos{true, true, 1};
/// tf2's TransformBroadcaster on /tf: reliable, 100.
inline constexpr QosProfile kTfQos{true, false, 100};
/// /clock: reliable (so best-effort and reliable subscribers both match), 1.
inline constexpr QosProfile kClockQos{true, false, 1};

/// A DDS entity's GUID (prefix and entity id, 16 bytes): the "gid" ROS 2's
/// graph messages name endpoints by.
using Gid = std::array<uint8_t, 16>;

/// "rt/r0/scan" for ROS topic "/r0/scan" (ROS 2's prefix for topics).
std::string dds_topic_name(std::string_view ros_topic);

class Participant {
 public:
  Participant() = default;
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  /// Joins `domain` (0..232). Configuration (interfaces, peers) comes from
  /// CYCLONEDDS_URI, as for any Cyclone DDS program. False with `error`.
  bool open(uint32_t domain, std::string& error);
  /// Leaves the domain: every writer and reader goes, remote peers see them
  /// disposed. Safe to call twice.
  void close();
  bool is_open() const { return participant_ > 0; }
  dds_entity_t handle() const { return participant_; }

  /// A writer of `desc`'s type on DDS topic `dds_topic`. Its user data holds
  /// the type's RIHS01 hash when the type is a ROS 2 type the bridge knows.
  /// 0 with `error` on failure.
  dds_entity_t create_writer(const std::string& dds_topic, const dds_topic_descriptor_t& desc,
                             const QosProfile& qos, std::string& error);
  /// A reader, as create_writer(); new samples make wake_fd() readable.
  dds_entity_t create_reader(const std::string& dds_topic, const dds_topic_descriptor_t& desc,
                             const QosProfile& qos, std::string& error);

  /// Readable when some reader has new samples; drain_wake() clears it.
  int wake_fd() const { return wake_fd_; }
  void drain_wake();

  /// The GUID of a participant, writer or reader.
  static Gid gid(dds_entity_t entity);

 private:
  dds_entity_t topic(const std::string& dds_topic, const dds_topic_descriptor_t& desc, std::string& error);
  dds_qos_t* endpoint_qos(const dds_topic_descriptor_t& desc, const QosProfile& qos);
  dds_entity_t create_endpoint(bool writer, const std::string& dds_topic, const dds_topic_descriptor_t& desc,
                               const QosProfile& qos, std::string& error);

  dds_entity_t participant_ = 0;
  dds_listener_t* listener_ = nullptr;
  int wake_fd_ = -1;
  std::unordered_map<std::string, dds_entity_t> topics_;
};

}  // namespace troupe::drivers::ros2
