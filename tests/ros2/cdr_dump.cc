// ros2_cdr_dump: the CDR bytes the bridge publishes, for every ROS 2 type it
// publishes, as JSON lines for cdr_check.mjs to hold against an independent
// serializer (@foxglove/rosmsg2-serialization).
//
// In one process: a node whose devices (one of each interface the bridge
// maps) publish fixed samples, the bridge itself (the ros2 driver, Cyclone
// DDS) on them, and Cyclone readers on every topic that take each sample as
// serialized bytes (dds_takecdr): the bytes a remote subscriber receives.
// Each line: {"topic", "type" (ROS name), "cdr" (hex), "expect" (field paths
// and the values the devices' samples imply)}.
#include <dds/dds.h>
#include <dds/ddsi/ddsi_serdata.h>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "drivers/ros2/ros2.h"
#include "drivers/ros2/ros2_msgs.h"
#include "runtime/node.h"
#include "tests/ros2/dds_env.h"

namespace {

using namespace troupe;
namespace ros2 = troupe::drivers::ros2;

constexpr uint64_t kStampUs = 12'345'678;  // every sample's time (simulated)
wire::Address addr(wire::Interface i, uint16_t index = 0) {
  return wire::Address(0, uint16_t(i), index);
}

// The devices: fixed samples every 50 ms, and the replies the bridge asks
// for. (The newest sample of each topic is what is compared: the ring's last
// transducer, the second bumper.)
class Source : public Driver {
 public:
  bool setup(Node& node, const DriverSetup& setup, std::string&) override {
    ids_.assign(setup.provides.begin(), setup.provides.end());
    return node.loop().start_timer(0, 50'000, this) != 0;
  }
  void on_timer(TimerId) override {
    for (DeviceId id : ids_) publish(id);
  }
  void on_request(DeviceId id, const wire::Message& req, RequestToken token) override {
    const wire::Address& a = node_->address(id);
    auto& b = node_->begin();
    switch (wire::Interface(a.iface())) {
      case wire::Interface::Ranger:
        if (req.header()->subtype() == uint8_t(wire::RangerReqSub::Geometry)) {
          const wire::Pose3d pose(0.1f, 0, 0.2f, 0, 0, 0), size(0, 0, 0, 0, 0, 0);
          const std::vector<wire::Pose3d> ring = {
              {0.1f, 0, 0, 0, 0, 0}, {0, 0.1f, 0, 0, 0, 1.5f}, {-0.1f, 0, 0, 0, 0, 3.0f}};
          const wire::Vec3 box(0.05f, 0.05f, 0.05f);
          auto body =
              wire::CreateRangerGeometry(b, &pose, &box, a.index() == 1 ? b.CreateVectorOfStructs(ring) : 0);
          return node_->ack(token, wire::Body::RangerGeometry, body.Union());
        } else {
          auto body = wire::CreateRangerConfig(b, -0.5f, 0.25f, 0.25f, 0.05f, 8.0f, 0.001f, 10.0f);
          return node_->ack(token, wire::Body::RangerConfig, body.Union());
        }
      case wire::Interface::Bumper: {
        const std::vector<wire::BumperDef> defs = {{wire::Pose2d(0.2f, 0.1f, 0.3f), 0.1f, 0},
                                                   {wire::Pose2d(0.2f, -0.1f, -0.3f), 0.1f, 0}};
        return node_->ack(token, wire::Body::BumperGeometry,
                          wire::CreateBumperGeometry(b, b.CreateVectorOfStructs(defs)).Union());
      }
      case wire::Interface::Map:
        if (req.header()->subtype() == uint8_t(wire::MapReqSub::Info)) {
          const wire::Pose2d origin(-1.0f, -2.0f, 0);
          return node_->ack(token, wire::Body::MapInfo, wire::CreateMapInfo(b, 4, 3, 0.5f, &origin).Union());
        } else {
          // 12 cells, four to a byte: free, occupied, unknown, free, ...
          const std::vector<uint8_t> cells = {0b00100100, 0b10010010, 0b01001001};
          return node_->ack(token, wire::Body::MapTile,
                            wire::CreateMapTile(b, 0, 0, 4, 3, b.CreateVector(cells)).Union());
        }
      default:
        return Driver::on_request(id, req, token);
    }
  }

 private:
  void publish(DeviceId id) {
    const wire::Address& a = node_->address(id);
    auto& b = node_->begin();
    switch (wire::Interface(a.iface())) {
      case wire::Interface::Position2d: {
        const wire::Pose2d pose(1.5f, -2.25f, 0.5f), vel(0.25f, 0, -0.125f);
        const wire::Cov2d cov(0.01f, 0.002f, 0, 0.02f, 0, 0.005f);
        auto body = wire::CreatePosition2dState(b, &pose, &vel, false, &cov);
        return node_->publish(id, 1, wire::Body::Position2dState, body.Union(), kStampUs);
      }
      case wire::Interface::Ranger: {
        const bool ring = a.index() == 1;
        const std::vector<uint16_t> mm =
            ring ? std::vector<uint16_t>{500, 1000, 250} : std::vector<uint16_t>{1000, 2500, 8000, 1234};
        const std::vector<uint8_t> strength = {10, 20, 30, 40};
        auto body = wire::CreateRangerScan(b, b.CreateVector(mm), 0.001f, ring ? 0 : -0.5f, ring ? 0 : 0.25f,
                                           ring ? 1.0f : 8.0f, ring ? 0 : b.CreateVector(strength));
        return node_->publish(id, 1, wire::Body::RangerScan, body.Union(), kStampUs);
      }
      case wire::Interface::Power: {
        wire::PowerStateBuilder p(b);
        p.add_volts(12.5f);
        p.add_percent(64.0f);
        p.add_charging(true);
        auto body = p.Finish();
        return node_->publish(id, 1, wire::Body::PowerState, body.Union(), kStampUs);
      }
      case wire::Interface::Imu: {
        const wire::Vec3 gyro(0, 0, 0.5f), accel(0.125f, 0, 9.75f), rpy(0, 0, 1.0f);
        return node_->publish(id, 1, wire::Body::ImuState,
                              wire::CreateImuState(b, &gyro, &accel, &rpy).Union(), kStampUs);
      }
      case wire::Interface::Bumper:
        return node_->publish(id, 1, wire::Body::BumperState, wire::CreateBumperState(b, 0b10, 2).Union(),
                              kStampUs);
      case wire::Interface::Localize: {
        const std::vector<wire::Hypothesis> h = {
            {wire::Pose2d(3, 4, 0.5f), wire::Cov2d(0.04f, 0, 0, 0.04f, 0, 0.01f), 1}};
        auto body = wire::CreateLocalizeState(b, b.CreateVectorOfStructs(h));
        return node_->publish(id, 1, wire::Body::LocalizeState, body.Union(), kStampUs);
      }
      case wire::Interface::Simulation: {
        auto body = wire::CreateSimClock(b, kStampUs, 123);
        return node_->publish(id, uint8_t(wire::SimulationDataSub::Clock), wire::Body::SimClock, body.Union(),
                              kStampUs);
      }
      default:
        return;
    }
  }

  std::vector<DeviceId> ids_;
};

struct Topic {
  const char* topic;
  const char* type;
  const dds_topic_descriptor_t* desc;
  bool reliable, latched;
  const char* expect;  // JSON object: field path -> value
};

// Every topic, and what the source's samples make of it. Floats are the
// float32 values the devices send; "Infinity"/"NaN" stand for those.
const Topic kTopics[] = {
    {"rt/odom", "nav_msgs/msg/Odometry", &nav_msgs_msg_dds__Odometry__desc, true, false,
     R"({"header.stamp.sec":12,"header.stamp.nanosec":345678000,"header.frame_id":"odom","child_frame_id":"base_link",
"pose.pose.position.x":1.5,"pose.pose.position.y":-2.25,"pose.pose.orientation.z":0.24740395925452294,
"pose.pose.orientation.w":0.9689124217106447,"pose.covariance.0":0.01,"pose.covariance.1":0.002,"pose.covariance.35":0.005,
"twist.twist.linear.x":0.25,"twist.twist.angular.z":-0.125})"},
    {"rt/tf", "tf2_msgs/msg/TFMessage", &tf2_msgs_msg_dds__TFMessage__desc, true, false,
     R"({"transforms.0.header.frame_id":"odom","transforms.0.child_frame_id":"base_link","transforms.0.transform.translation.x":1.5})"},
    {"rt/tf_static", "tf2_msgs/msg/TFMessage", &tf2_msgs_msg_dds__TFMessage__desc, true, true,
     R"({"transforms.0.header.frame_id":"base_link","transforms.0.child_frame_id":"base_scan","transforms.0.transform.translation.x":0.1,
"transforms.0.transform.translation.z":0.2})"},
    {"rt/scan", "sensor_msgs/msg/LaserScan", &sensor_msgs_msg_dds__LaserScan__desc, false, false,
     R"({"header.frame_id":"base_scan","angle_min":-0.5,"angle_max":0.25,"angle_increment":0.25,"scan_time":0.1,
"range_min":0.05,"range_max":8,"ranges.0":1,"ranges.1":2.5,"ranges.2":"Infinity","ranges.3":1.234,"intensities.3":40})"},
    {"rt/sonar_1", "sensor_msgs/msg/Range", &sensor_msgs_msg_dds__Range__desc, false, false,
     R"({"header.frame_id":"sonar_1_2","radiation_type":0,"field_of_view":0.75,"min_range":0.05,"max_range":1,"range":0.25,"variance":0})"},
    {"rt/battery", "sensor_msgs/msg/BatteryState", &sensor_msgs_msg_dds__BatteryState__desc, true, false,
     R"({"header.frame_id":"base_link","voltage":12.5,"current":"NaN","percentage":0.64,"power_supply_status":1,
"present":true,"location":"","serial_number":""})"},
    {"rt/imu", "sensor_msgs/msg/Imu", &sensor_msgs_msg_dds__Imu__desc, false, false,
     R"({"header.frame_id":"base_link","angular_velocity.z":0.5,"linear_acceleration.z":9.75,
"orientation.z":0.479425538604203,"orientation_covariance.0":0})"},
    {"rt/bumper", "sensor_msgs/msg/Range", &sensor_msgs_msg_dds__Range__desc, false, false,
     R"({"header.frame_id":"bumper_1","min_range":0,"max_range":0,"range":"-Infinity"})"},
    {"rt/amcl_pose", "geometry_msgs/msg/PoseWithCovarianceStamped",
     &geometry_msgs_msg_dds__PoseWithCovarianceStamped__desc, true, true,
     R"({"header.frame_id":"map","pose.pose.position.x":3,"pose.pose.position.y":4,"pose.covariance.0":0.04,"pose.covariance.35":0.01})"},
    {"rt/map", "nav_msgs/msg/OccupancyGrid", &nav_msgs_msg_dds__OccupancyGrid__desc, true, true,
     R"({"header.frame_id":"map","info.width":4,"info.height":3,"info.resolution":0.5,"info.origin.position.x":-1,
"info.origin.position.y":-2,"data.0":0,"data.1":100,"data.2":-1,"data.3":0,"data.4":-1,"data.11":100})"},
    {"rt/clock", "rosgraph_msgs/msg/Clock", &rosgraph_msgs_msg_dds__Clock__desc, false, false,
     R"({"clock.sec":12,"clock.nanosec":345678000})"},
    {"rt/diagnostics", "diagnostic_msgs/msg/DiagnosticArray", &diagnostic_msgs_msg_dds__DiagnosticArray__desc,
     true, false,
     R"({"header.frame_id":"","status.0.hardware_id":"position2d:0","status.0.values.0.key":"topic","status.0.values.0.value":"/odom"})"},
    {"ros_discovery_info", "rmw_dds_common/msg/ParticipantEntitiesInfo",
     &rmw_dds_common_msg_dds__ParticipantEntitiesInfo__desc, true, true,
     R"({"node_entities_info_seq.0.node_name":"troupe_bridge","node_entities_info_seq.0.node_namespace":"/"})"},
};

std::string hex(const std::vector<uint8_t>& bytes) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (uint8_t v : bytes) {
    out += digits[v >> 4];
    out += digits[v & 15];
  }
  return out;
}

// The serialized form of the newest sample `reader` holds, or empty.
std::vector<uint8_t> take_cdr(dds_entity_t reader) {
  ddsi_serdata* sd = nullptr;
  dds_sample_info_t info;
  std::vector<uint8_t> out;
  while (dds_takecdr(reader, &sd, 1, &info, DDS_ANY_STATE) == 1) {
    if (info.valid_data) {
      out.resize(ddsi_serdata_size(sd));
      ddsi_serdata_to_ser(sd, 0, out.size(), out.data());
    }
    ddsi_serdata_unref(sd);
  }
  return out;
}

}  // namespace

int main() {
  troupe::testing::ros2::DdsDomain domain;
  if (domain.id() < 0) {
    std::fprintf(stderr, "ros2_cdr_dump: no free DDS domain\n");
    return 1;
  }
  setenv("CYCLONEDDS_URI", troupe::testing::ros2::cyclone_loopback_config().c_str(), 1);
  setenv("ROS_DOMAIN_ID", std::to_string(domain.id()).c_str(), 1);

  Node::Options options;
  options.port = 0;
  Node node(options);
  using I = wire::Interface;
  const wire::Address sources[] = {addr(I::Position2d), addr(I::Ranger, 0), addr(I::Ranger, 1),
                                   addr(I::Power),      addr(I::Imu),       addr(I::Bumper),
                                   addr(I::Localize),   addr(I::Map),       addr(I::Simulation)};
  std::vector<DeviceId> provided;
  auto source = std::make_unique<Source>();
  for (const wire::Address& a : sources) provided.push_back(node.add_device(a, source.get(), "source"));
  const DeviceId status = node.add_device(addr(I::Opaque), nullptr, "ros2");
  std::string error;
  DriverSetup s1;
  s1.name = "source";
  s1.provides = provided;
  DriverSetup s2;
  s2.name = "ros2";
  const DeviceId status_list[] = {status};
  s2.provides = status_list;
  s2.required = provided;
  auto bridge = std::make_unique<ros2::Ros2Bridge>();
  if (!node.add_driver(std::move(source), s1, error) || !node.add_driver(std::move(bridge), s2, error) ||
      !node.start(error)) {
    std::fprintf(stderr, "ros2_cdr_dump: %s\n", error.c_str());
    return 1;
  }

  // The subscribers: another participant, as a remote node would be.
  const dds_entity_t participant = dds_create_participant(dds_domainid_t(domain.id()), nullptr, nullptr);
  std::vector<dds_entity_t> readers;
  for (const Topic& t : kTopics) {
    dds_qos_t* q = dds_create_qos();
    dds_qset_reliability(q, t.reliable ? DDS_RELIABILITY_RELIABLE : DDS_RELIABILITY_BEST_EFFORT, DDS_SECS(1));
    dds_qset_durability(q, t.latched ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
    const dds_entity_t topic = dds_create_topic(participant, t.desc, t.topic, nullptr, nullptr);
    readers.push_back(dds_create_reader(participant, topic, q, nullptr));
    dds_delete_qos(q);
  }
  // The newest sample of each topic, after two ticks of the bridge (its
  // geometry requests answered, /tf_static complete).
  std::map<size_t, std::vector<uint8_t>> taken;
  for (int waited_ms = 0; waited_ms < 30000 && (taken.size() < std::size(kTopics) || waited_ms < 2500);
       waited_ms += 20) {
    node.poll(20'000);
    for (size_t i = 0; i < readers.size(); ++i) {
      std::vector<uint8_t> bytes = take_cdr(readers[i]);
      if (!bytes.empty()) taken[i] = std::move(bytes);
    }
  }
  for (size_t i = 0; i < std::size(kTopics); ++i) {
    const Topic& t = kTopics[i];
    if (taken.count(i) == 0) {
      std::fprintf(stderr, "ros2_cdr_dump: nothing came on %s\n", t.topic);
      return 1;
    }
    std::string expect = t.expect;
    for (char& c : expect) c = c == '\n' ? ' ' : c;
    std::printf("{\"topic\":\"%s\",\"type\":\"%s\",\"cdr\":\"%s\",\"expect\":%s}\n", t.topic, t.type,
                hex(taken[i]).c_str(), expect.c_str());
  }
  dds_delete(participant);
  node.shutdown();
  return 0;
}
