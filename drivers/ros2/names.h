// ROS 2 names as the bridge makes them: topics "/r0/scan", frames
// "r0/base_scan", and the checks ROS 2 applies to a name's parts.
#pragma once

#include <cstdint>
#include <string>

namespace troupe::drivers::ros2 {

/// True when `name` is a valid ROS 2 name token (a node name, or one part of
/// a namespace or topic): letters, digits and '_', not starting with a
/// digit, no "__".
bool valid_ros_token(const std::string& name);
/// True when every '/'-separated part of `path` is a valid token.
bool valid_ros_path(const std::string& path);

/// "scan" for index 0, "scan_2" for index 2: the names of a robot's second
/// and later devices of one interface.
std::string suffixed(const std::string& name, uint16_t index);
/// "r0/base_scan", or "base_scan" in the root namespace: a frame name.
std::string in_ns(const std::string& ns, const std::string& name);
/// "/r0/scan", or "/scan": a topic name.
std::string topic_in_ns(const std::string& ns, const std::string& name);

}  // namespace troupe::drivers::ros2
