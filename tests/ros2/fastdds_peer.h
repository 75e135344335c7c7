// A ROS 2 peer on eProsima Fast DDS, the DDS vendor the bridge does not use:
// what a ROS 2 node on rmw_fastrtps is to the bridge. Its types come from
// fastddsgen run on the bridge's ROS 2 definitions (ros2_msgs.idl), so both
// ends agree only if both follow ROS 2's names and plain CDR.
#pragma once

#include <array>
#include <cstdint>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

namespace troupe::testing::ros2 {

/// What discovery said about a remote writer or reader.
struct Endpoint {
  bool writer = false;
  std::string topic, type;
  /// The endpoint's user data (ROS 2 Iron+: "typehash=RIHS01_...;").
  std::string user_data;
  std::array<uint8_t, 16> guid{};
};

/// As in the bridge (drivers/ros2/dds.h).
struct PeerQos {
  bool reliable = true;
  bool transient_local = false;
  int32_t depth = 10;
};

class FastDdsPeer : public eprosima::fastdds::dds::DomainParticipantListener {
 public:
  /// Joins `domain` over UDP on loopback, finding peers at 127.0.0.1's
  /// well-known ports (no multicast).
  explicit FastDdsPeer(int domain);
  ~FastDdsPeer() override;
  bool ok() const { return participant_ != nullptr; }

  /// A reader or writer of a registered type (register_type<T>() first).
  eprosima::fastdds::dds::DataReader* reader(const std::string& topic, const std::string& type,
                                             const PeerQos& qos);
  eprosima::fastdds::dds::DataWriter* writer(const std::string& topic, const std::string& type,
                                             const PeerQos& qos);
  /// Registers a fastddsgen PubSubType; returns its DDS type name.
  template <class PubSubType>
  std::string register_type() {
    eprosima::fastdds::dds::TypeSupport ts(new PubSubType());
    ts.register_type(participant_);
    return ts.get_type_name();
  }
  /// Registers a type named `name` whose samples are raw serialized bytes
  /// (std::vector<uint8_t>, encapsulation header included): for sending
  /// what no serializer would.
  void register_raw_type(const std::string& name);

  /// Endpoints discovered so far.
  std::vector<Endpoint> endpoints() const;
  /// Waits (polling, at most `timeout_ms`) until `pred` holds for some endpoint.
  bool wait_endpoint(const std::function<bool(const Endpoint&)>& pred, int timeout_ms) const;
  /// User data of the remote participants discovered.
  std::vector<std::string> participant_user_data() const;

  void on_publisher_discovery(eprosima::fastdds::dds::DomainParticipant*,
                              eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override;
  void on_subscriber_discovery(eprosima::fastdds::dds::DomainParticipant*,
                               eprosima::fastrtps::rtps::ReaderDiscoveryInfo&& info) override;
  void on_participant_discovery(eprosima::fastdds::dds::DomainParticipant*,
                                eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override;

 private:
  eprosima::fastdds::dds::Topic* topic(const std::string& name, const std::string& type);

  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  mutable std::mutex mutex_;
  std::vector<Endpoint> endpoints_;
  std::vector<std::string> participants_;
};

/// The next sample of `reader`, waiting at most `timeout_ms`. False when
/// none came.
template <class T>
bool take(eprosima::fastdds::dds::DataReader* reader, T& out, int timeout_ms) {
  eprosima::fastdds::dds::SampleInfo info;
  while (true) {
    while (reader->take_next_sample(&out, &info) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) return true;
    }
    if (timeout_ms <= 0) return false;
    const int step = std::min(timeout_ms, 100);
    reader->wait_for_unread_message(eprosima::fastrtps::Duration_t(0, uint32_t(step) * 1'000'000u));
    timeout_ms -= step;
  }
}

/// Publications matched by `reader` now.
int matched(eprosima::fastdds::dds::DataReader* reader);
/// Subscriptions matched by `writer` now.
int matched(eprosima::fastdds::dds::DataWriter* writer);

}  // namespace troupe::testing::ros2
