#include "drivers/ros2/dds.h"

#include <pthread.h>
#include <signal.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cstring>

#include "drivers/ros2/ros2_type_hashes.h"

namespace troupe::drivers::ros2 {

namespace {

// ROS 2's participant user data: the security enclave the node runs in; "/"
// when it runs without security, as here.
constexpr char kParticipantUserData[] = "enclave=/;";

// Runs on a Cyclone thread: only pokes the descriptor the node's loop watches.
void on_data_available(dds_entity_t /*reader*/, void* arg) {
  const uint64_t one = 1;
  const int fd = *static_cast<const int*>(arg);
  // A full counter (2^64 - 1 wake-ups unread) cannot happen; nothing to do on error.
  [[maybe_unused]] ssize_t n = write(fd, &one, sizeof one);
}

}  // namespace

std::string dds_topic_name(std::string_view ros_topic) {
  std::string out = "rt";
  if (ros_topic.empty() || ros_topic.front() != '/') out += '/';
  out += ros_topic;
  return out;
}

Participant::~Participant() {
  close();
}

bool Participant::open(uint32_t domain, std::string& error) {
  close();
  wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake_fd_ < 0) {
    error = std::string("eventfd: ") + strerror(errno);
    return false;
  }
  dds_qos_t* qos = dds_create_qos();
  dds_qset_userdata(qos, kParticipantUserData, sizeof kParticipantUserData - 1);
  // Cyclone starts its threads here; they inherit this mask. With every
  // signal blocked in them, SIGINT and SIGTERM reach the node's loop (which
  // stops cleanly) rather than a DDS thread (which would end the process).
  sigset_t all, previous;
  sigfillset(&all);
  pthread_sigmask(SIG_SETMASK, &all, &previous);
  participant_ = dds_create_participant(domain, qos, nullptr);
  pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  dds_delete_qos(qos);
  if (participant_ < 0) {
    error = "cannot join DDS domain " + std::to_string(domain) + ": " + dds_strretcode(participant_) +
            " (is CYCLONEDDS_URI valid?)";
    participant_ = 0;
    close();
    return false;
  }
  listener_ = dds_create_listener(&wake_fd_);
  dds_lset_data_available(listener_, on_data_available);
  return true;
}

void Participant::close() {
  // Deleting the participant deletes its endpoints and waits for listeners
  // still running, so the descriptor can go after it.
  if (participant_ > 0) dds_delete(participant_);
  participant_ = 0;
  topics_.clear();
  if (listener_ != nullptr) dds_delete_listener(listener_);
  listener_ = nullptr;
  if (wake_fd_ >= 0) ::close(wake_fd_);
  wake_fd_ = -1;
}

dds_entity_t Participant::topic(const std::string& dds_topic, const dds_topic_descriptor_t& desc,
                                std::string& error) {
  auto it = topics_.find(dds_topic);
  if (it != topics_.end()) return it->second;
  dds_entity_t t = dds_create_topic(participant_, &desc, dds_topic.c_str(), nullptr, nullptr);
  if (t < 0) {
    error = "cannot create DDS topic " + dds_topic + " (" + desc.m_typename + "): " + dds_strretcode(t);
    return 0;
  }
  topics_.emplace(dds_topic, t);
  return t;
}

dds_qos_t* Participant::endpoint_qos(const dds_topic_descriptor_t& desc, const QosProfile& profile) {
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, profile.reliable ? DDS_RELIABILITY_RELIABLE : DDS_RELIABILITY_BEST_EFFORT,
                       DDS_MSECS(100));
  dds_qset_durability(qos,
                      profile.transient_local ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, profile.depth);
  // ROS 2 Iron and later compare this with the type they expect.
  if (const RosTypeInfo* info = find_ros_type(desc.m_typename)) {
    const std::string user_data = std::string("typehash=") + info->hash + ";";
    dds_qset_userdata(qos, user_data.data(), user_data.size());
  }
  return qos;
}

dds_entity_t Participant::create_writer(const std::string& dds_topic, const dds_topic_descriptor_t& desc,
                                        const QosProfile& qos, std::string& error) {
  return create_endpoint(true, dds_topic, desc, qos, error);
}

dds_entity_t Participant::create_reader(const std::string& dds_topic, const dds_topic_descriptor_t& desc,
                                        const QosProfile& qos, std::string& error) {
  return create_endpoint(false, dds_topic, desc, qos, error);
}

dds_entity_t Participant::create_endpoint(bool writer, const std::string& dds_topic,
                                          const dds_topic_descriptor_t& desc, const QosProfile& profile,
                                          std::string& error) {
  dds_entity_t t = topic(dds_topic, desc, error);
  if (t == 0) return 0;
  dds_qos_t* qos = endpoint_qos(desc, profile);
  const dds_entity_t e = writer ? dds_create_writer(participant_, t, qos, nullptr)
                                : dds_create_reader(participant_, t, qos, listener_);
  dds_delete_qos(qos);
  if (e < 0) {
    error = std::string("cannot create a DDS ") + (writer ? "writer" : "reader") + " on " + dds_topic + ": " +
            dds_strretcode(e);
    return 0;
  }
  return e;
}

void Participant::drain_wake() {
  uint64_t count = 0;
  [[maybe_unused]] ssize_t n = read(wake_fd_, &count, sizeof count);
}

Gid Participant::gid(dds_entity_t entity) {
  dds_guid_t guid{};
  dds_get_guid(entity, &guid);
  Gid out{};
  static_assert(sizeof guid.v == sizeof(Gid));
  std::memcpy(out.data(), guid.v, out.size());
  return out;
}

}  // namespace troupe::drivers::ros2
