#include "tests/ros2/fastdds_peer.h"

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

#include <chrono>
#include <cstring>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/TopicDataType.hpp>
#include <thread>

// Debian 12's libfastrtps 2.9 deletes its statistics readers and writers
// through a pointer to a base of another size, which AddressSanitizer
// reports (new-delete-type-mismatch) when a participant goes: a defect of
// the library, not of the code under test. Everything else stays checked.
#if defined(__SANITIZE_ADDRESS__)
extern "C" const char* __asan_default_options() {
  return "new_delete_type_mismatch=0";
}
#endif

namespace troupe::testing::ros2 {

namespace dds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;

namespace {

// Serialized bytes in, the same bytes out: a type only for sending
// malformed samples.
class RawType : public dds::TopicDataType {
 public:
  explicit RawType(const std::string& name) {
    setName(name.c_str());
    m_typeSize = 64 * 1024;
    m_isGetKeyDefined = false;
  }
  bool serialize(void* data, rtps::SerializedPayload_t* payload) override {
    const auto* bytes = static_cast<const std::vector<uint8_t>*>(data);
    if (bytes->size() > payload->max_size) return false;
    std::memcpy(payload->data, bytes->data(), bytes->size());
    payload->length = uint32_t(bytes->size());
    return true;
  }
  bool deserialize(rtps::SerializedPayload_t* payload, void* data) override {
    auto* bytes = static_cast<std::vector<uint8_t>*>(data);
    bytes->assign(payload->data, payload->data + payload->length);
    return true;
  }
  std::function<uint32_t()> getSerializedSizeProvider(void* data) override {
    return [data] { return uint32_t(static_cast<const std::vector<uint8_t>*>(data)->size()); };
  }
  void* createData() override { return new std::vector<uint8_t>(); }
  void deleteData(void* data) override { delete static_cast<std::vector<uint8_t>*>(data); }
  bool getKey(void*, rtps::InstanceHandle_t*, bool) override { return false; }
};

std::array<uint8_t, 16> guid_bytes(const rtps::GUID_t& g) {
  std::array<uint8_t, 16> out{};
  std::memcpy(out.data(), g.guidPrefix.value, 12);
  std::memcpy(out.data() + 12, g.entityId.value, 4);
  return out;
}

template <class Qos>
void apply(Qos& q, const PeerQos& p) {
  q.reliability().kind = p.reliable ? dds::RELIABLE_RELIABILITY_QOS : dds::BEST_EFFORT_RELIABILITY_QOS;
  q.durability().kind =
      p.transient_local ? dds::TRANSIENT_LOCAL_DURABILITY_QOS : dds::VOLATILE_DURABILITY_QOS;
  q.history().kind = dds::KEEP_LAST_HISTORY_QOS;
  q.history().depth = p.depth;
}

}  // namespace

FastDdsPeer::FastDdsPeer(int domain) {
  dds::DomainParticipantQos q;
  q.name("troupe_test_peer");
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  udp->interfaceWhiteList.push_back("127.0.0.1");
  // Initial peers on 127.0.0.1 without a port mean the well-known discovery
  // ports of participants 0..maxInitialPeersRange there.
  udp->maxInitialPeersRange = 20;
  // Bursts of a swarm's scans overflow the kernel's default 208 KiB (what
  // ROS 2's DDS tuning notes say too); the kernel caps this at rmem_max.
  udp->receiveBufferSize = 4 * 1024 * 1024;
  q.transport().user_transports.push_back(udp);
  q.transport().use_builtin_transports = false;
  rtps::Locator_t peer;
  rtps::IPLocator::setIPv4(peer, "127.0.0.1");
  q.wire_protocol().builtin.initialPeersList.push_back(peer);
  participant_ = dds::DomainParticipantFactory::get_instance()->create_participant(uint32_t(domain), q, this,
                                                                                   dds::StatusMask::none());
  if (participant_ == nullptr) return;
  publisher_ = participant_->create_publisher(dds::PUBLISHER_QOS_DEFAULT);
  subscriber_ = participant_->create_subscriber(dds::SUBSCRIBER_QOS_DEFAULT);
}

FastDdsPeer::~FastDdsPeer() {
  if (participant_ == nullptr) return;
  participant_->delete_contained_entities();
  dds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
}

void FastDdsPeer::register_raw_type(const std::string& name) {
  dds::TypeSupport ts(new RawType(name));
  ts.register_type(participant_);
}

dds::Topic* FastDdsPeer::topic(const std::string& name, const std::string& type) {
  if (dds::TopicDescription* d = participant_->lookup_topicdescription(name))
    return static_cast<dds::Topic*>(d);
  return participant_->create_topic(name, type, dds::TOPIC_QOS_DEFAULT);
}

dds::DataReader* FastDdsPeer::reader(const std::string& name, const std::string& type, const PeerQos& qos) {
  dds::Topic* t = topic(name, type);
  if (t == nullptr) return nullptr;
  dds::DataReaderQos q = dds::DATAREADER_QOS_DEFAULT;
  apply(q, qos);
  return subscriber_->create_datareader(t, q);
}

dds::DataWriter* FastDdsPeer::writer(const std::string& name, const std::string& type, const PeerQos& qos) {
  dds::Topic* t = topic(name, type);
  if (t == nullptr) return nullptr;
  dds::DataWriterQos q = dds::DATAWRITER_QOS_DEFAULT;
  apply(q, qos);
  return publisher_->create_datawriter(t, q);
}

std::vector<Endpoint> FastDdsPeer::endpoints() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return endpoints_;
}

bool FastDdsPeer::wait_endpoint(const std::function<bool(const Endpoint&)>& pred, int timeout_ms) const {
  for (int waited = 0;; waited += 50) {
    for (const Endpoint& e : endpoints()) {
      if (pred(e)) return true;
    }
    if (waited >= timeout_ms) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

std::vector<std::string> FastDdsPeer::participant_user_data() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return participants_;
}

void FastDdsPeer::on_publisher_discovery(dds::DomainParticipant*, rtps::WriterDiscoveryInfo&& info) {
  if (info.status != rtps::WriterDiscoveryInfo::DISCOVERED_WRITER) return;
  const auto& ud = info.info.m_qos.m_userData;
  std::lock_guard<std::mutex> lock(mutex_);
  endpoints_.push_back({true, info.info.topicName().to_string(), info.info.typeName().to_string(),
                        std::string(ud.begin(), ud.end()), guid_bytes(info.info.guid())});
}

void FastDdsPeer::on_subscriber_discovery(dds::DomainParticipant*, rtps::ReaderDiscoveryInfo&& info) {
  if (info.status != rtps::ReaderDiscoveryInfo::DISCOVERED_READER) return;
  const auto& ud = info.info.m_qos.m_userData;
  std::lock_guard<std::mutex> lock(mutex_);
  endpoints_.push_back({false, info.info.topicName().to_string(), info.info.typeName().to_string(),
                        std::string(ud.begin(), ud.end()), guid_bytes(info.info.guid())});
}

void FastDdsPeer::on_participant_discovery(dds::DomainParticipant*, rtps::ParticipantDiscoveryInfo&& info) {
  if (info.status != rtps::ParticipantDiscoveryInfo::DISCOVERED_PARTICIPANT) return;
  std::lock_guard<std::mutex> lock(mutex_);
  participants_.emplace_back(info.info.m_userData.begin(), info.info.m_userData.end());
}

int matched(dds::DataReader* reader) {
  dds::SubscriptionMatchedStatus s;
  reader->get_subscription_matched_status(s);
  return s.current_count;
}

int matched(dds::DataWriter* writer) {
  dds::PublicationMatchedStatus s;
  writer->get_publication_matched_status(s);
  return s.current_count;
}

}  // namespace troupe::testing::ros2
