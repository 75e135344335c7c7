#include "drivers/ros2/graph.h"

#include <cstring>

#include "drivers/ros2/ros2_msgs.h"

namespace troupe::drivers::ros2 {

namespace {

using Gid_ = rmw_dds_common_msg_dds__Gid_;

// Bounded strings (string<=256) are arrays in the generated struct.
void copy_bounded(char (&out)[257], const std::string& text) {
  std::strncpy(out, text.c_str(), sizeof out - 1);
  out[sizeof out - 1] = '\0';
}

}  // namespace

bool Graph::open(Participant& participant, std::string name, std::string ns, std::string& error) {
  participant_ = &participant;
  name_ = std::move(name);
  ns_ = std::move(ns);
  writer_ = participant.create_writer(
      "ros_discovery_info", rmw_dds_common_msg_dds__ParticipantEntitiesInfo__desc, kLatchedQos, error);
  return writer_ != 0;
}

void Graph::add_writer(dds_entity_t writer) {
  writers_.push_back(Participant::gid(writer));
}
void Graph::add_reader(dds_entity_t reader) {
  readers_.push_back(Participant::gid(reader));
}

void Graph::publish() {
  if (writer_ == 0) return;
  std::vector<Gid_> readers(readers_.size()), writers(writers_.size());
  for (size_t i = 0; i < readers_.size(); ++i) std::memcpy(readers[i].data, readers_[i].data(), 16);
  for (size_t i = 0; i < writers_.size(); ++i) std::memcpy(writers[i].data, writers_[i].data(), 16);

  rmw_dds_common_msg_dds__NodeEntitiesInfo_ node{};
  copy_bounded(node.node_namespace, ns_);
  copy_bounded(node.node_name, name_);
  node.reader_gid_seq = {uint32_t(readers.size()), uint32_t(readers.size()), readers.data(), false};
  node.writer_gid_seq = {uint32_t(writers.size()), uint32_t(writers.size()), writers.data(), false};

  rmw_dds_common_msg_dds__ParticipantEntitiesInfo_ info{};
  const Gid self = Participant::gid(participant_->handle());
  std::memcpy(info.gid.data, self.data(), 16);
  info.node_entities_info_seq = {1, 1, &node, false};
  dds_write(writer_, &info);
}

}  // namespace troupe::drivers::ros2
