// The bridge's pieces on their own: ROS 2 type hashes against the ones ROS 2
// Jazzy publishes, the conversions, the command checks, stamps and names,
// and the configs it refuses.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>

#include "drivers/ros2/convert.h"
#include "drivers/ros2/names.h"
#include "drivers/ros2/ros2.h"
#include "drivers/ros2/ros2_type_hashes.h"
#include "drivers/ros2/stamps.h"
#include "runtime/node.h"
#include "runtime/node_config.h"

namespace {

using namespace troupe::drivers::ros2;
namespace wire = troupe::wire;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// A FlatBuffers table built by `make`, read back as T.
template <typename T, typename Make>
const T* build(flatbuffers::FlatBufferBuilder& b, Make make) {
  b.Finish(make(b));
  return flatbuffers::GetRoot<T>(b.GetBufferPointer());
}

TEST(Ros2TypeHash, EveryTypeHashesAsRos2JazzyPublishesIt) {
  // From ROS 2 Jazzy's generated type descriptions (rosidl): each type's
  // RIHS01 hash as `ros2 topic info -v` shows it.
  const std::map<std::string, std::string> jazzy = {
      {"builtin_interfaces/msg/Time", "b106235e25a4c5ed35098aa0a61a3ee9c9b18d197f398b0e4206cea9acf9c197"},
      {"std_msgs/msg/Header", "f49fb3ae2cf070f793645ff749683ac6b06203e41c891e17701b1cb597ce6a01"},
      {"geometry_msgs/msg/Point", "6963084842a9b04494d6b2941d11444708d892da2f4b09843b9c43f42a7f6881"},
      {"geometry_msgs/msg/Quaternion", "8a765f66778c8ff7c8ab94afcc590a2ed5325a1d9a076ffff38fbce36f458684"},
      {"geometry_msgs/msg/Vector3", "cc12fe83e4c02719f1ce8070bfd14aecd40f75a96696a67a2a1f37f7dbb0765d"},
      {"geometry_msgs/msg/Pose", "d501954e9476cea2996984e812054b68026ae0bfae789d9a10b23daf35cc90fa"},
      {"geometry_msgs/msg/PoseWithCovariance",
       "9a7c0fd234b7f45c6098745ecccd773ca1085670e64107135397aee31c02e1bb"},
      {"geometry_msgs/msg/PoseWithCovarianceStamped",
       "26432f9803e43727d3c8f668d1fdb3c630f548af631e2f4e31382371bfea3b6e"},
      {"geometry_msgs/msg/Transform", "beb83fbe698636351461f6f35d1abb20010c43d55374d81bd041f1ba2581fddc"},
      {"geometry_msgs/msg/TransformStamped",
       "0a241f87d04668d94099cbb5ba11691d5ad32c2f29682e4eb5653424bd275206"},
      {"geometry_msgs/msg/Twist", "9c45bf16fe0983d80e3cfe750d6835843d265a9a6c46bd2e609fcddde6fb8d2a"},
      {"geometry_msgs/msg/TwistWithCovariance",
       "49f574f033f095d8b6cd1beaca5ca7925e296e84af1716d16c89d38b059c8c18"},
      {"nav_msgs/msg/MapMetaData", "2772d4b2000ef2b35dbaeb80fd3946c1369f817fb4f75677d916d27c17d763c8"},
      {"nav_msgs/msg/OccupancyGrid", "8d348150c12913a31ee0ec170fbf25089e4745d17035792a1ba94d6f0bc0cfc7"},
      {"nav_msgs/msg/Odometry", "3cc97dc7fb7502f8714462c526d369e35b603cfc34d946e3f2eda2766dfec6e0"},
      {"sensor_msgs/msg/LaserScan", "64c191398013af96509d518dac71d5164f9382553fce5c1f8cca5be7924bd828"},
      {"sensor_msgs/msg/Range", "b42b62562e93cbfe9d42b82fe5994dfa3d63d7d5c90a317981703f7388adff3a"},
      {"sensor_msgs/msg/BatteryState", "4bee5dfce981c98faa6828b868307a0a73f992ed0789f374ee96c8f840e69741"},
      {"sensor_msgs/msg/Imu", "7d9a00ff131080897a5ec7e26e315954b8eae3353c3f995c55faf71574000b5b"},
      {"tf2_msgs/msg/TFMessage", "e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087"},
      {"rosgraph_msgs/msg/Clock", "692f7a66e93a3c83e71765d033b60349ba68023a8c689a79e48078bcb5c58564"},
      {"diagnostic_msgs/msg/KeyValue", "d68081eaa540288c5440753baecef0c4e16e81a5f78ad68902ded5100413bb42"},
      {"diagnostic_msgs/msg/DiagnosticStatus",
       "b0e3e692ea2d54a8af2f4ef1930e81556a2db55216b771f8a7d2724ed47bf0e4"},
      {"diagnostic_msgs/msg/DiagnosticArray",
       "5a8a36efb05fb25070fa0fb3810290c0e6cd4862b54a8fb975a1ee8dc55a333e"},
      {"rmw_dds_common/msg/Gid", "ab6f21cfbb0a6dbb837161e1110c2051a2850ed9f9c53944d7115d9bcebedf71"},
      {"rmw_dds_common/msg/NodeEntitiesInfo",
       "8ffef65ee2d088c63b1e8fcd31e800ba9fc8dbe0ee15ca60d1676de5218087a7"},
      {"rmw_dds_common/msg/ParticipantEntitiesInfo",
       "91a0593bacdcc50ea9bdcf849a938b128412cc1ea821245c663bcd26f83c295e"},
  };
  size_t checked = 0;
  for (const RosTypeInfo& t : kRosTypes) {
    auto it = jazzy.find(t.ros_name);
    ASSERT_NE(it, jazzy.end()) << t.ros_name << " has no reference hash here";
    EXPECT_EQ(std::string(t.hash), "RIHS01_" + it->second) << t.ros_name;
    checked++;
  }
  EXPECT_EQ(checked, jazzy.size());
  ASSERT_NE(find_ros_type("sensor_msgs::msg::dds_::LaserScan_"), nullptr);
  EXPECT_STREQ(find_ros_type("sensor_msgs::msg::dds_::LaserScan_")->ros_name, "sensor_msgs/msg/LaserScan");
  EXPECT_EQ(find_ros_type("sensor_msgs::msg::dds_::Nothing_"), nullptr);
}

TEST(Ros2Convert, QuaternionsAndCovariances) {
  for (double yaw : {0.0, 0.5, -2.0, 3.1}) EXPECT_NEAR(yaw_of(quaternion_from_rpy(0, 0, yaw)), yaw, 1e-12);
  const Quaternion q = quaternion_from_rpy(0.1, -0.2, 0.3);
  EXPECT_NEAR(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z, 1.0, 1e-12);

  const wire::Cov2d c(1, 2, 3, 4, 5, 6);  // xx xy xa yy ya aa
  double m[36];
  covariance_6x6(c, m);
  EXPECT_EQ(m[0], 1);
  EXPECT_EQ(m[1], 2);
  EXPECT_EQ(m[6], 2);
  EXPECT_EQ(m[5], 3);
  EXPECT_EQ(m[30], 3);
  EXPECT_EQ(m[7], 4);
  EXPECT_EQ(m[11], 5);
  EXPECT_EQ(m[31], 5);
  EXPECT_EQ(m[35], 6);
  EXPECT_EQ(m[14], 0) << "z is not estimated";
  const wire::Cov2d back = covariance_2d(m);
  EXPECT_EQ(back.xx(), 1);
  EXPECT_EQ(back.xa(), 3);
  EXPECT_EQ(back.aa(), 6);
}

TEST(Ros2Convert, OdometryAndItsTransform) {
  flatbuffers::FlatBufferBuilder b;
  const wire::Pose2d pose(1.5f, -2.0f, 0.75f), vel(0.3f, 0.0f, -0.1f);
  const auto* s =
      build<wire::Position2dState>(b, [&](auto& fb) { return wire::CreatePosition2dState(fb, &pose, &vel); });
  const std::string odom = "r0/odom", base = "r0/base_link";
  Odometry o;
  fill_odometry(*s, ros_time(12'345'678), odom, base, o);
  EXPECT_EQ(o.header.stamp.sec, 12);
  EXPECT_EQ(o.header.stamp.nanosec, 345'678'000u);
  EXPECT_STREQ(o.header.frame_id, "r0/odom");
  EXPECT_STREQ(o.child_frame_id, "r0/base_link");
  EXPECT_EQ(o.pose.pose.position.x, 1.5);
  EXPECT_EQ(o.pose.pose.position.y, -2.0);
  EXPECT_NEAR(yaw_of(o.pose.pose.orientation), 0.75, 1e-7);
  EXPECT_EQ(o.twist.twist.linear.x, double(0.3f));
  EXPECT_EQ(o.twist.twist.angular.z, double(-0.1f));
  for (double v : o.pose.covariance) EXPECT_EQ(v, 0) << "unknown when the device gives none";
  TransformStamped t;
  fill_odom_transform(o, t);
  EXPECT_STREQ(t.header.frame_id, "r0/odom");
  EXPECT_STREQ(t.child_frame_id, "r0/base_link");
  EXPECT_EQ(t.transform.translation.x, 1.5);
}

TEST(Ros2Convert, ScansRingsAndNoReturn) {
  flatbuffers::FlatBufferBuilder b;
  const std::vector<uint16_t> mm = {500, 8000, 9000, 1234};
  const auto* scan = build<wire::RangerScan>(b, [&](auto& fb) {
    return wire::CreateRangerScan(fb, fb.CreateVector(mm), 0.001f, -1.0f, 0.5f, 8.0f);
  });
  ASSERT_TRUE(is_scan(*scan));
  EXPECT_FLOAT_EQ(range_at(*scan, 0), 0.5f);
  EXPECT_TRUE(std::isinf(range_at(*scan, 1))) << "at max_range: no return";
  EXPECT_TRUE(std::isinf(range_at(*scan, 2)));
  LaserScan out;
  std::vector<float> ranges, intensities;
  const std::string frame = "r0/base_scan";
  fill_laser_scan(*scan, ros_time(1), frame, 0.02f, 0.1f, ranges, intensities, out);
  EXPECT_EQ(out.angle_min, -1.0f);
  EXPECT_EQ(out.angle_max, -1.0f + 3 * 0.5f);
  EXPECT_EQ(out.range_min, 0.02f);
  EXPECT_EQ(out.range_max, 8.0f);
  EXPECT_EQ(out.scan_time, 0.1f);
  ASSERT_EQ(out.ranges._length, 4u);
  EXPECT_FLOAT_EQ(out.ranges._buffer[3], 1.234f);
  EXPECT_EQ(out.intensities._length, 0u);

  flatbuffers::FlatBufferBuilder rb;
  const auto* ring = build<wire::RangerScan>(rb, [&](auto& fb) {
    return wire::CreateRangerScan(fb, fb.CreateVector(mm), 0.001f, 0.0f, 0.0f, 5.0f);
  });
  EXPECT_FALSE(is_scan(*ring)) << "separate transducers leave angular_res 0";
  Range r;
  fill_sonar_range(*ring, 3, ros_time(1), frame, 0.35f, 0.1f, r);
  EXPECT_EQ(r.radiation_type, sensor_msgs_msg_dds__Range_Constants_ULTRASOUND);
  EXPECT_FLOAT_EQ(r.range, 1.234f);
  EXPECT_EQ(r.field_of_view, 0.35f);
  EXPECT_EQ(r.max_range, 5.0f);

  fill_bumper_range(true, ros_time(1), frame, r);
  EXPECT_EQ(r.min_range, r.max_range) << "a fixed-distance detector";
  EXPECT_TRUE(std::isinf(r.range) && r.range < 0) << "-Inf: contact";
  fill_bumper_range(false, ros_time(1), frame, r);
  EXPECT_TRUE(std::isinf(r.range) && r.range > 0);
}

TEST(Ros2Convert, BatteryAndImuSayWhatWasNotMeasured) {
  flatbuffers::FlatBufferBuilder b;
  const auto* p = build<wire::PowerState>(b, [&](auto& fb) {
    wire::PowerStateBuilder ps(fb);
    ps.add_volts(12.0f);
    ps.add_watts(24.0f);
    ps.add_percent(80.0f);
    ps.add_charging(false);
    return ps.Finish();
  });
  const std::string frame = "base_link";
  BatteryState bs;
  fill_battery(*p, ros_time(1), frame, bs);
  EXPECT_EQ(bs.voltage, 12.0f);
  EXPECT_EQ(bs.current, -2.0f) << "negative while discharging";
  EXPECT_FLOAT_EQ(bs.percentage, 0.8f);
  EXPECT_TRUE(std::isnan(bs.charge) && std::isnan(bs.temperature) && std::isnan(bs.capacity));
  EXPECT_EQ(bs.power_supply_status,
            sensor_msgs_msg_dds__BatteryState_Constants_POWER_SUPPLY_STATUS_DISCHARGING);
  EXPECT_TRUE(bs.present);

  flatbuffers::FlatBufferBuilder ib;
  const wire::Vec3 gyro(0, 0, 0.5f);
  const auto* imu = build<wire::ImuState>(ib, [&](auto& fb) { return wire::CreateImuState(fb, &gyro); });
  Imu out;
  fill_imu(*imu, ros_time(1), frame, out);
  EXPECT_EQ(out.angular_velocity.z, 0.5);
  EXPECT_EQ(out.angular_velocity_covariance[0], 0);
  EXPECT_EQ(out.orientation_covariance[0], -1) << "no orientation measured";
  EXPECT_EQ(out.linear_acceleration_covariance[0], -1);
}

TEST(Ros2Command, CmdVelIsClampedOrRefusedNeverPassedOnAsItIs) {
  const VelLimits limits{1.0, 2.0};
  Twist t{};
  wire::Pose2d vel;
  std::string why;
  t.linear.x = 0.5;
  t.angular.z = -1.0;
  EXPECT_EQ(vel_from_twist(t, limits, vel, why), Verdict::Ok);
  EXPECT_EQ(vel.x(), 0.5f);
  EXPECT_EQ(vel.a(), -1.0f);

  t.linear.x = 1e30;
  t.linear.y = -5;
  t.angular.z = -1e9;
  EXPECT_EQ(vel_from_twist(t, limits, vel, why), Verdict::Clamped);
  EXPECT_EQ(vel.x(), 1.0f);
  EXPECT_EQ(vel.y(), -1.0f);
  EXPECT_EQ(vel.a(), -2.0f);
  EXPECT_NE(why.find("clamped"), std::string::npos);

  for (double bad : {kNaN, kInf, -kInf}) {
    for (int field = 0; field < 6; ++field) {
      Twist u{};
      double* f[6] = {&u.linear.x, &u.linear.y, &u.linear.z, &u.angular.x, &u.angular.y, &u.angular.z};
      *f[field] = bad;
      EXPECT_EQ(vel_from_twist(u, limits, vel, why), Verdict::Refused) << "field " << field;
    }
  }
}

TEST(Ros2Command, InitialPoseIsCheckedBeforeTheLocalizerSeesIt) {
  PoseWithCovarianceStamped msg{};
  msg.pose.pose.position.x = 2;
  msg.pose.pose.position.y = -1;
  msg.pose.pose.orientation = quaternion_from_rpy(0, 0, 1.0);
  msg.pose.covariance[0] = 0.25;
  msg.pose.covariance[7] = 0.25;
  msg.pose.covariance[35] = 0.06;
  wire::Pose2d mean;
  wire::Cov2d cov;
  std::string why;
  ASSERT_TRUE(pose_from_initialpose(msg, mean, cov, why)) << why;
  EXPECT_EQ(mean.x(), 2.0f);
  EXPECT_NEAR(mean.a(), 1.0f, 1e-6);
  EXPECT_FLOAT_EQ(cov.aa(), 0.06f);

  PoseWithCovarianceStamped bad = msg;
  bad.pose.pose.orientation.w = kNaN;
  EXPECT_FALSE(pose_from_initialpose(bad, mean, cov, why));
  bad = msg;
  bad.pose.covariance[20] = kInf;
  EXPECT_FALSE(pose_from_initialpose(bad, mean, cov, why));
  bad = msg;
  bad.pose.covariance[0] = -1;
  EXPECT_FALSE(pose_from_initialpose(bad, mean, cov, why));
}

TEST(Ros2Stamps, SimulatedTimeIsKeptWallTimeFollowsTheFastestArrival) {
  StampMap sim(true);
  EXPECT_EQ(sim.to_ros_us(1'500'000, 0, 99), 1'500'000u);

  // A robot whose clock reads 1000 s behind this host's, its samples
  // arriving 2 ms, then 0.5 ms, then 3 ms after they were stamped.
  StampMap wall(false);
  const uint64_t offset = 1'000'000'000;
  EXPECT_EQ(wall.to_ros_us(5'000'000, 7, 5'000'000 + offset + 2000), 5'000'000 + offset + 2000);
  EXPECT_EQ(wall.to_ros_us(5'100'000, 7, 5'100'000 + offset + 500), 5'100'000 + offset + 500);
  EXPECT_EQ(wall.to_ros_us(5'200'000, 7, 5'200'000 + offset + 3000), 5'200'000 + offset + 500)
      << "the least delay seen is the estimate";
  // Another robot has its own estimate.
  EXPECT_EQ(wall.to_ros_us(10, 8, 10 + 4000), 10u + 4000);
  // Robot 7 rebooted: its clock restarted near zero, a jump far beyond the
  // estimate; a new estimate starts.
  EXPECT_EQ(wall.to_ros_us(1000, 7, 5'300'000 + offset + 1000), 5'300'000 + offset + 1000);
}

TEST(Ros2Names, TokensTopicsFrames) {
  EXPECT_TRUE(valid_ros_token("r0"));
  EXPECT_TRUE(valid_ros_token("base_link"));
  EXPECT_FALSE(valid_ros_token(""));
  EXPECT_FALSE(valid_ros_token("0r"));
  EXPECT_FALSE(valid_ros_token("a__b"));
  EXPECT_FALSE(valid_ros_token("a-b"));
  EXPECT_FALSE(valid_ros_token("a/b"));
  EXPECT_TRUE(valid_ros_path("fleet/r0"));
  EXPECT_FALSE(valid_ros_path("fleet//r0"));
  EXPECT_EQ(suffixed("scan", 0), "scan");
  EXPECT_EQ(suffixed("scan", 2), "scan_2");
  EXPECT_EQ(in_ns("r0", "base_link"), "r0/base_link");
  EXPECT_EQ(in_ns("", "map"), "map");
  EXPECT_EQ(topic_in_ns("r0", "odom"), "/r0/odom");
  EXPECT_EQ(topic_in_ns("", "map"), "/map");
}

}  // namespace

namespace {

using namespace troupe;

// Devices of any interface, publishing nothing: what the bridge is set up on.
class Devices : public Driver {
 public:
  bool setup(Node&, const DriverSetup&, std::string&) override { return true; }
};

// The bridge set up on devices at `addrs`, with options from `json` (the
// driver's table); false and `error` when it refuses.
bool bridge_on(const std::vector<wire::Address>& addrs, const std::string& json, std::string& error) {
  Node node(Node::Options{});
  auto devices = std::make_unique<Devices>();
  std::vector<DeviceId> ids;
  for (const wire::Address& a : addrs) ids.push_back(node.add_device(a, devices.get(), "devices"));
  const DeviceId status =
      node.add_device(wire::Address(0, uint16_t(wire::Interface::Opaque), 9), nullptr, "ros2");
  DriverSetup d;
  d.provides = ids;
  if (!node.add_driver(std::move(devices), d, error)) return false;
  std::vector<uint8_t> config;
  const std::string text = R"({ "drivers": [ { "driver_type": "ros2", "driver": )" + json +
                           R"(, "uses": ["position2d:0"], "provides": ["opaque:9"] } ] })";
  if (!parse_config_json(text, "test.json", config, error)) return false;
  DriverSetup b;
  b.instance = config::GetNodeConfig(config.data())->drivers()->Get(0);
  b.name = "ros2";
  const DeviceId status_list[] = {status};
  b.provides = status_list;
  b.required = ids;
  return node.add_driver(std::make_unique<drivers::ros2::Ros2Bridge>(), b, error);
}

const wire::Address kBase(0, uint16_t(wire::Interface::Position2d), 0);

// The bridge's commands go through Node::command(): the target driver gets
// the newest one at the end of the loop iteration, as a client's.
class Base : public Driver {
 public:
  bool setup(Node&, const DriverSetup&, std::string&) override { return true; }
  void on_command(DeviceId, const wire::Message& m) override {
    commands.push_back(m.body_as_Position2dVel()->vel()->x());
  }
  std::vector<float> commands;
};

TEST(Ros2Setup, CommandsReachAnotherDriversDeviceNewestFirst) {
  Node node(Node::Options{});
  auto base = std::make_unique<Base>();
  Base* seen = base.get();
  const DeviceId id = node.add_device(kBase, base.get(), "base");
  std::string error;
  DriverSetup setup;
  const DeviceId ids[] = {id};
  setup.provides = ids;
  ASSERT_TRUE(node.add_driver(std::move(base), setup, error)) << error;
  for (float v : {0.1f, 0.2f}) {
    auto& b = node.begin();
    const wire::Pose2d vel(v, 0, 0);
    auto body = wire::CreatePosition2dVel(b, &vel);
    node.command(id, uint8_t(wire::Position2dCmdSub::Vel), wire::Body::Position2dVel, body.Union());
  }
  EXPECT_TRUE(seen->commands.empty()) << "delivered at the end of the loop iteration";
  node.poll(0);
  EXPECT_EQ(seen->commands, std::vector<float>{0.2f}) << "the newest replaced the older";
}

TEST(Ros2Setup, RefusesWhatItCannotBridgeBeforeTouchingTheNetwork) {
  std::string error;
  EXPECT_FALSE(bridge_on({kBase, wire::Address(0, uint16_t(wire::Interface::Fiducial), 0)}, "{}", error));
  EXPECT_NE(error.find("no ROS 2 message for fiducial"), std::string::npos) << error;
  EXPECT_FALSE(bridge_on({kBase}, R"({ "namespaces": ["robot 1"] })", error));
  EXPECT_NE(error.find("'robot 1' is not a valid ROS name"), std::string::npos) << error;
  EXPECT_FALSE(bridge_on({kBase}, R"({ "domain_id": 300 })", error));
  EXPECT_NE(error.find("outside 0..232"), std::string::npos) << error;
  EXPECT_FALSE(bridge_on({kBase}, R"({ "base_frame": "base link" })", error));
  EXPECT_NE(error.find("not a valid ROS name"), std::string::npos) << error;
  EXPECT_FALSE(bridge_on({kBase, wire::Address(0, uint16_t(wire::Interface::Position2d), 1)},
                         R"({ "topics": ["odom", "odom"] })", error));
  EXPECT_NE(error.find("would both publish /odom"), std::string::npos) << error;
  EXPECT_FALSE(bridge_on({kBase}, R"({ "max_linear": -1 })", error));
  EXPECT_NE(error.find("max_linear"), std::string::npos) << error;
}

}  // namespace
