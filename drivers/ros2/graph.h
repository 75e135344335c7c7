// The ROS 2 graph: what `ros2 node list` and `ros2 node info` read to see the
// bridge as a node. Every ROS 2 participant publishes, on the DDS topic
// "ros_discovery_info" (latched), which nodes it hosts and the GUIDs of each
// node's readers and writers (rmw_dds_common/ParticipantEntitiesInfo); DDS
// discovery alone shows only topics.
#pragma once

#include <string>
#include <vector>

#include "drivers/ros2/dds.h"

namespace troupe::drivers::ros2 {

class Graph {
 public:
  /// Creates the ros_discovery_info writer on `participant` for one node
  /// named `name` in namespace `ns` ("/" or "/fleet"). False with `error`.
  bool open(Participant& participant, std::string name, std::string ns, std::string& error);
  /// Endpoints of the node; publish() tells the graph.
  void add_writer(dds_entity_t writer);
  void add_reader(dds_entity_t reader);
  /// Publishes the participant's entry (again): after endpoints changed.
  void publish();

  const std::string& name() const { return name_; }

 private:
  Participant* participant_ = nullptr;
  dds_entity_t writer_ = 0;
  std::string name_, ns_;
  std::vector<Gid> readers_, writers_;
};

}  // namespace troupe::drivers::ros2
