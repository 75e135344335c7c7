// The bridge between real programs and another vendor's DDS: troupe-sim
// serves a world, `troupe-ros2` (Cyclone DDS) bridges it, and a ROS 2 peer on
// Fast DDS with types from the ROS 2 definitions reads the topics and
// drives the robot. The simulator's ground truth (simulation:0) and a Troupe
// client reading the same devices are what the ROS 2 side is checked against.
#include <limits>
#include <map>
#include <set>

#include "tests/ros2/bridge_fixture.h"

namespace {

using namespace troupe::testing;
using namespace troupe::testing::ros2;

// --print-config is a one-shot command: it prints the config of a node that
// is there, and fails at once, saying why, for one that is not.
TEST_F(BridgeTest, PrintConfigPrintsTheBridgeOfANodeAndFailsForAnAbsentOne) {
  start_sim("room.world");
  ASSERT_FALSE(HasFatalFailure());
  ProgramResult there = run_to_end({kBin + "/troupe-ros2", "127.0.0.1:" + std::to_string(sim_port_), "--print-config"},
                                   kWaitMs);
  EXPECT_EQ(there.status, 0) << there.err;
  EXPECT_NE(there.out.find("\"driver_type\": \"ros2\""), std::string::npos) << there.out;
  const uint16_t nobody = free_port();
  ProgramResult absent =
      run_to_end({kBin + "/troupe-ros2", "127.0.0.1:" + std::to_string(nobody), "--print-config"}, kWaitMs);
  EXPECT_EQ(absent.status, 1) << absent.out << absent.err;
  EXPECT_NE(absent.err.find("cannot read the devices of 127.0.0.1:" + std::to_string(nobody)), std::string::npos)
      << absent.err;
  EXPECT_TRUE(absent.out.empty()) << absent.out;
}

TEST_F(BridgeTest, ScanAndOdometryReachAFastDdsSubscriberAsTheSimulatorSentThem) {
  start_sim("room.world");
  start_bridge();
  FastDdsPeer peer(domain_.id());
  ASSERT_TRUE(peer.ok());
  const std::string scan_type = peer.register_type<sensor_msgs::msg::dds_::LaserScan_PubSubType>();
  const std::string odom_type = peer.register_type<nav_msgs::msg::dds_::Odometry_PubSubType>();
  EXPECT_EQ(scan_type, "sensor_msgs::msg::dds_::LaserScan_");
  EXPECT_EQ(odom_type, "nav_msgs::msg::dds_::Odometry_");
  fdds::DataReader* scans = peer.reader("rt/r0/scan", scan_type, kSensorQos);
  fdds::DataReader* odoms = peer.reader("rt/r0/odom", odom_type, kReliable);
  ASSERT_TRUE(scans && odoms);

  // The same devices read by a Troupe client, sample by sample, by stamp.
  std::map<uint64_t, std::vector<float>> troupe_scans;
  std::map<uint64_t, std::array<float, 4>> troupe_odoms;  // x, y, a, vx
  float min_angle = 0, res = 0, max_range = 0;
  auto& c = sim_client();
  troupe::wire::Address ranger{}, base{};
  ASSERT_TRUE(c.resolve("r0/ranger:0", ranger) && c.resolve("r0/position2d:0", base));
  ASSERT_TRUE(c.open(ranger, troupe::wire::Access::Read) && c.open(base, troupe::wire::Access::Read));
  c.add_data_handler([&](const troupe::wire::Message& m) {
    const uint64_t t = troupe::wire::time_us(*m.header());
    if (const auto* s = m.body_as_RangerScan(); s && s->ranges()) {
      std::vector<float> r;
      for (uint16_t v : *s->ranges()) {
        const float m_ = float(v) * s->scale();
        r.push_back(m_ >= s->max_range() ? std::numeric_limits<float>::infinity() : m_);
      }
      troupe_scans[t] = r;
      min_angle = s->min_angle();
      res = s->angular_res();
      max_range = s->max_range();
    } else if (const auto* p = m.body_as_Position2dState(); p && p->pose() && p->vel()) {
      troupe_odoms[t] = {p->pose()->x(), p->pose()->y(), p->pose()->a(), p->vel()->x()};
    }
  });

  int scans_checked = 0, odoms_checked = 0;
  for (int waited = 0; waited < kWaitMs && (scans_checked < 5 || odoms_checked < 5); waited += 50) {
    c.spin_for(50);
    LaserScan s;
    while (take(scans, s, 0)) {
      auto it = troupe_scans.find(stamp_us(s.header().stamp()));
      if (it == troupe_scans.end()) continue;
      EXPECT_EQ(s.header().frame_id(), "r0/base_scan");
      EXPECT_EQ(s.angle_min(), min_angle);
      EXPECT_EQ(s.angle_increment(), res);
      EXPECT_FLOAT_EQ(s.angle_max(), min_angle + float(it->second.size() - 1) * res);
      EXPECT_EQ(s.range_max(), max_range);
      EXPECT_EQ(s.ranges(), it->second);
      scans_checked++;
    }
    Odometry o;
    while (take(odoms, o, 0)) {
      auto it = troupe_odoms.find(stamp_us(o.header().stamp()));
      if (it == troupe_odoms.end()) continue;
      EXPECT_EQ(o.header().frame_id(), "r0/odom");
      EXPECT_EQ(o.child_frame_id(), "r0/base_link");
      EXPECT_EQ(o.pose().pose().position().x(), double(it->second[0]));
      EXPECT_EQ(o.pose().pose().position().y(), double(it->second[1]));
      EXPECT_NEAR(yaw_of(o.pose().pose().orientation()), it->second[2], 1e-6);
      EXPECT_EQ(o.twist().twist().linear().x(), double(it->second[3]));
      odoms_checked++;
    }
  }
  EXPECT_GE(scans_checked, 5) << "LaserScans matched to the simulator's scans by stamp";
  EXPECT_GE(odoms_checked, 5) << "Odometry matched to the simulator's by stamp";
}

TEST_F(BridgeTest, CmdVelFromFastDdsDrivesTheSimulatedRobot) {
  start_sim("room.world");
  start_bridge();
  FastDdsPeer peer(domain_.id());
  ASSERT_TRUE(peer.ok());
  fdds::DataWriter* cmd = peer.writer(
      "rt/r0/cmd_vel", peer.register_type<geometry_msgs::msg::dds_::Twist_PubSubType>(), kReliable);
  ASSERT_TRUE(cmd && wait_matched(cmd)) << "the bridge's cmd_vel reader was not matched";

  // r0 starts at (-2.5, 2.5) facing east (room.world), the way clear.
  const troupe::client::Pose2 start = ground_truth();
  ASSERT_TRUE(drive_until(cmd, twist(0.3, 0), [&] {
    const auto p = ground_truth();
    return std::hypot(p.x - start.x, p.y - start.y) > 0.3;
  })) << "cmd_vel did not move the robot";
  const troupe::client::Pose2 moved = ground_truth();
  EXPECT_GT(moved.x - start.x, 0.29) << "forward is east";
  EXPECT_NEAR(moved.y, start.y, 0.02);

  // Turning on the spot, counter-clockwise.
  ASSERT_TRUE(drive_until(cmd, twist(0, 0.5), [&] { return ground_truth().a - moved.a > 0.3; }));
  Twist zero;
  cmd->write(&zero);
  EXPECT_TRUE(stopped()) << "a zero twist stops the robot";
}

TEST_F(BridgeTest, ANonFiniteCmdVelIsRefusedAndStopsTheBase) {
  start_sim("room.world");
  start_bridge();
  FastDdsPeer peer(domain_.id());
  ASSERT_TRUE(peer.ok());
  fdds::DataWriter* cmd = peer.writer(
      "rt/r0/cmd_vel", peer.register_type<geometry_msgs::msg::dds_::Twist_PubSubType>(), kReliable);
  fdds::DataReader* diag =
      peer.reader("rt/diagnostics",
                  peer.register_type<diagnostic_msgs::msg::dds_::DiagnosticArray_PubSubType>(), kReliable);
  ASSERT_TRUE(cmd && diag && wait_matched(cmd));

  const troupe::client::Pose2 start = ground_truth();
  ASSERT_TRUE(drive_until(cmd, twist(0.3, 0), [&] { return ground_truth().x - start.x > 0.1; }));
  // Once, and never again: the base must not keep the last speed.
  Twist bad = twist(std::numeric_limits<double>::quiet_NaN(), 0);
  cmd->write(&bad);
  EXPECT_TRUE(stopped()) << "the base kept moving after a NaN cmd_vel";
  EXPECT_TRUE(bridge_.wait_for("not a finite number", true, kWaitMs));

  // /diagnostics counts the refusal on the base.
  bool counted = false;
  DiagnosticArray a;
  for (int waited = 0; waited < kWaitMs && !counted; waited += 100) {
    if (!take(diag, a, 100)) continue;
    for (const auto& s : a.status()) {
      if (s.hardware_id() != "r0/position2d:0") continue;
      for (const auto& kv : s.values()) counted |= kv.key() == "refused" && kv.value() == "1";
    }
  }
  EXPECT_TRUE(counted);

  // The bridge goes on serving: a valid command moves the robot again.
  const troupe::client::Pose2 here = ground_truth();
  EXPECT_TRUE(drive_until(cmd, twist(0.3, 0), [&] { return ground_truth().x - here.x > 0.1; }));
}

TEST_F(BridgeTest, AHugeCmdVelIsClampedToTheLimits) {
  start_sim("room.world");
  start_bridge({"--max-linear", "0.2", "--max-angular", "0.3"});
  FastDdsPeer peer(domain_.id());
  ASSERT_TRUE(peer.ok());
  fdds::DataWriter* cmd = peer.writer(
      "rt/r0/cmd_vel", peer.register_type<geometry_msgs::msg::dds_::Twist_PubSubType>(), kReliable);
  ASSERT_TRUE(cmd && wait_matched(cmd));

  // The robot itself could go 0.5 m/s (room.world): the bridge's limit is
  // what holds it at 0.2, and the turn at -0.3 rad/s.
  auto& c = sim_client();
  troupe::client::Position2dProxy base(
      c, troupe::wire::Address(0, uint16_t(troupe::wire::Interface::Position2d), 0));
  ASSERT_TRUE(c.open(base.address(), troupe::wire::Access::Read));
  double fastest = 0, fastest_turn = 0;
  ASSERT_TRUE(drive_until(cmd, twist(1e30, -1e30), [&] {
    fastest = std::max(fastest, std::fabs(base.velocity().x));
    fastest_turn = std::max(fastest_turn, std::fabs(base.velocity().a));
    return base.velocity().x > 0.19f && base.velocity().a < -0.29f;
  })) << "the robot did not reach the clamped speed";
  Twist huge = twist(1e30, -1e30);
  for (int i = 0; i < 10; ++i) {
    cmd->write(&huge);
    c.spin_for(100);
    fastest = std::max(fastest, std::fabs(base.velocity().x));
    fastest_turn = std::max(fastest_turn, std::fabs(base.velocity().a));
  }
  EXPECT_LE(fastest, 0.2 + 1e-4);
  EXPECT_LE(fastest_turn, 0.3 + 1e-4);
  EXPECT_TRUE(bridge_.wait_for("clamped to", true, kWaitMs));
}

TEST_F(BridgeTest, MalformedSamplesOnCmdVelChangeNothing) {
  start_sim("room.world");
  start_bridge();
  // Another participant whose cmd_vel type writes whatever bytes it is given.
  FastDdsPeer raw(domain_.id());
  ASSERT_TRUE(raw.ok());
  raw.register_raw_type("geometry_msgs::msg::dds_::Twist_");
  fdds::DataWriter* junk = raw.writer("rt/r0/cmd_vel", "geometry_msgs::msg::dds_::Twist_", kReliable);
  ASSERT_TRUE(junk && wait_matched(junk));

  const troupe::client::Pose2 start = ground_truth();
  std::vector<std::vector<uint8_t>> samples = {
      {0x00, 0x01, 0x00},                                      // shorter than the encapsulation header
      {0x00, 0x01, 0x00, 0x00, 0x9a, 0x99, 0x99, 0x99, 0x99},  // a Twist cut after 5 of its 48 bytes
      {0x7f, 0x7f, 0x00, 0x00},                                // an encapsulation nobody defines
  };
  samples.back().resize(4 + 48, 0x3f);
  for (auto& s : samples) ASSERT_TRUE(junk->write(&s));
  // Time for them to arrive and, were they taken, to move the robot.
  sim_client().spin_for(1500);
  const troupe::client::Pose2 after = ground_truth();
  EXPECT_NEAR(after.x, start.x, 1e-4);
  EXPECT_NEAR(after.y, start.y, 1e-4);
  EXPECT_NEAR(after.a, start.a, 1e-4);

  // The bridge still takes well-formed commands.
  ASSERT_TRUE(bridge_.running());
  FastDdsPeer peer(domain_.id());
  fdds::DataWriter* cmd = peer.writer(
      "rt/r0/cmd_vel", peer.register_type<geometry_msgs::msg::dds_::Twist_PubSubType>(), kReliable);
  ASSERT_TRUE(cmd && wait_matched(cmd));
  EXPECT_TRUE(drive_until(cmd, twist(0.3, 0), [&] { return ground_truth().x - start.x > 0.1; }));
}

TEST_F(BridgeTest, ASilentDeviceIsReportedStaleItsTopicsStayAndDataComesBack) {
  start_sim("room.world");
  start_bridge();
  FastDdsPeer peer(domain_.id());
  ASSERT_TRUE(peer.ok());
  fdds::DataReader* scans = peer.reader(
      "rt/r0/scan", peer.register_type<sensor_msgs::msg::dds_::LaserScan_PubSubType>(), kSensorQos);
  fdds::DataReader* diag =
      peer.reader("rt/diagnostics",
                  peer.register_type<diagnostic_msgs::msg::dds_::DiagnosticArray_PubSubType>(), kReliable);
  LaserScan s;
  ASSERT_TRUE(take(scans, s, kWaitMs));

  auto ranger_level = [&](int want) {
    DiagnosticArray a;
    for (int waited = 0; waited < kWaitMs; waited += 100) {
      if (!take(diag, a, 100)) continue;
      for (const auto& st : a.status()) {
        if (st.hardware_id() == "r0/ranger:0" && st.level() == want) return true;
      }
    }
    return false;
  };
  EXPECT_TRUE(ranger_level(0)) << "OK while scans flow";

  sim_.kill_hard();  // gone without a goodbye
  EXPECT_TRUE(ranger_level(3)) << "STALE once the scans stopped";
  EXPECT_TRUE(bridge_.wait_for("r0/ranger:0 sent nothing", true, kWaitMs));
  EXPECT_EQ(matched(scans), 1) << "the scan topic's writer is still there";
  while (take(scans, s, 0)) {
  }

  start_sim("room.world");  // the same port: passthrough reconnects
  EXPECT_TRUE(take(scans, s, kWaitMs)) << "scans again after the simulator came back";
  EXPECT_TRUE(ranger_level(0));
  EXPECT_TRUE(bridge_.running());
}

TEST_F(BridgeTest, RosGraphSeesTheNodeItsEndpointsAndTheirTypeHashes) {
  start_sim("room.world");
  start_bridge();
  FastDdsPeer peer(domain_.id());
  ASSERT_TRUE(peer.ok());
  fdds::DataReader* graph = peer.reader(
      "ros_discovery_info",
      peer.register_type<rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_PubSubType>(), kLatched);
  ASSERT_TRUE(graph);

  // ROS 2 Jazzy's hashes of these types, as its own type descriptions give them.
  const std::map<std::string, std::string> hashes = {
      {"rt/r0/scan", "RIHS01_64c191398013af96509d518dac71d5164f9382553fce5c1f8cca5be7924bd828"},
      {"rt/r0/odom", "RIHS01_3cc97dc7fb7502f8714462c526d369e35b603cfc34d946e3f2eda2766dfec6e0"},
      {"rt/tf", "RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087"},
      {"rt/clock", "RIHS01_692f7a66e93a3c83e71765d033b60349ba68023a8c689a79e48078bcb5c58564"},
      {"rt/map", "RIHS01_8d348150c12913a31ee0ec170fbf25089e4745d17035792a1ba94d6f0bc0cfc7"},
      {"rt/r0/cmd_vel", "RIHS01_9c45bf16fe0983d80e3cfe750d6835843d265a9a6c46bd2e609fcddde6fb8d2a"},
  };
  for (const auto& [topic, hash] : hashes) {
    const std::string want = "typehash=" + hash + ";";
    EXPECT_TRUE(peer.wait_endpoint([&](const Endpoint& e) { return e.topic == topic && e.user_data == want; },
                                   kWaitMs))
        << topic << " with " << want;
  }
  const auto participants = peer.participant_user_data();
  EXPECT_NE(std::find(participants.begin(), participants.end(), "enclave=/;"), participants.end());

  // ros_discovery_info names the node and, by GUID, the endpoints above.
  std::set<std::array<uint8_t, 16>> writers, readers;
  for (const Endpoint& e : peer.endpoints()) {
    if (e.topic == "rt/r0/scan" && e.writer) writers.insert(e.guid);
    if (e.topic == "rt/r0/cmd_vel" && !e.writer) readers.insert(e.guid);
  }
  ASSERT_EQ(writers.size(), 1u);
  ASSERT_EQ(readers.size(), 1u);
  bool found = false;
  ParticipantEntitiesInfo info;
  for (int waited = 0; waited < kWaitMs && !found; waited += 100) {
    if (!take(graph, info, 100)) continue;
    for (const auto& node : info.node_entities_info_seq()) {
      if (std::string(node.node_name()) != "troupe_bridge" || std::string(node.node_namespace()) != "/")
        continue;
      bool has_writer = false, has_reader = false;
      for (const auto& g : node.writer_gid_seq()) has_writer |= writers.count(g.data()) > 0;
      for (const auto& g : node.reader_gid_seq()) has_reader |= readers.count(g.data()) > 0;
      found = has_writer && has_reader;
    }
  }
  EXPECT_TRUE(found) << "no ros_discovery_info entry names the node with its scan writer and cmd_vel reader";
}

TEST_F(BridgeTest, TransformsClockAndALatchedMap) {
  start_sim("room.world");
  start_bridge();
  ASSERT_TRUE(bridge_.wait_for("published on /map", true, kWaitMs));
  // Readers made after the map was published: latched topics reach late joiners.
  FastDdsPeer peer(domain_.id());
  ASSERT_TRUE(peer.ok());
  const std::string tf_type = peer.register_type<tf2_msgs::msg::dds_::TFMessage_PubSubType>();
  fdds::DataReader* tf_static = peer.reader("rt/tf_static", tf_type, kLatched);
  fdds::DataReader* tf = peer.reader("rt/tf", tf_type, kReliable);
  fdds::DataReader* clock =
      peer.reader("rt/clock", peer.register_type<rosgraph_msgs::msg::dds_::Clock_PubSubType>(), kSensorQos);
  fdds::DataReader* map =
      peer.reader("rt/map", peer.register_type<nav_msgs::msg::dds_::OccupancyGrid_PubSubType>(), kLatched);

  OccupancyGrid grid;
  ASSERT_TRUE(take(map, grid, kWaitMs));
  EXPECT_EQ(grid.header().frame_id(), "map");
  EXPECT_EQ(grid.info().width() * grid.info().height(), grid.data().size());
  std::map<int, size_t> values;
  for (int8_t v : grid.data()) values[v]++;
  EXPECT_GT(values[100], 0u) << "walls";
  EXPECT_GT(values[0], 0u) << "free floor";
  EXPECT_EQ(values.size(), size_t(values.count(-1) + 2)) << "only 0, 100 and -1";

  // The laser's pose on the robot, as the device states it.
  troupe::wire::Pose3d laser{};
  std::vector<troupe::wire::Pose3d> elements;
  troupe::client::RangerProxy ranger(sim_client(),
                                     troupe::wire::Address(0, uint16_t(troupe::wire::Interface::Ranger), 0));
  ASSERT_TRUE(ranger.geometry(laser, elements));
  TFMessage t;
  bool laser_tf = false;
  for (int waited = 0; waited < kWaitMs && !laser_tf; waited += 100) {
    if (!take(tf_static, t, 100)) continue;
    for (const auto& x : t.transforms()) {
      if (x.child_frame_id() != "r0/base_scan") continue;
      laser_tf = true;
      EXPECT_EQ(x.header().frame_id(), "r0/base_link");
      EXPECT_NEAR(x.transform().translation().x(), laser.x(), 1e-6);
      EXPECT_NEAR(x.transform().translation().y(), laser.y(), 1e-6);
      EXPECT_NEAR(yaw_of(x.transform().rotation()), laser.yaw(), 1e-6);
    }
  }
  EXPECT_TRUE(laser_tf) << "base_link -> base_scan on /tf_static";

  ASSERT_TRUE(take(tf, t, kWaitMs));
  ASSERT_EQ(t.transforms().size(), 1u);
  EXPECT_EQ(t.transforms()[0].header().frame_id(), "r0/odom");
  EXPECT_EQ(t.transforms()[0].child_frame_id(), "r0/base_link");

  Clock a, b;
  ASSERT_TRUE(take(clock, a, kWaitMs));
  ASSERT_TRUE(take(clock, b, kWaitMs));
  EXPECT_GT(stamp_us(b.clock()), stamp_us(a.clock())) << "simulated time moves on";
}

TEST_F(BridgeTest, EveryRobotOfTheSwarmHasItsTopics) {
  start_sim("swarm100.world", {"--no-ctrl"});
  start_bridge();
  FastDdsPeer peer(domain_.id());
  ASSERT_TRUE(peer.ok());
  fdds::DataReader* sonar =
      peer.reader("rt/b42/sonar", peer.register_type<sensor_msgs::msg::dds_::Range_PubSubType>(), kSensorQos);
  ASSERT_TRUE(sonar);
  for (int i = 0; i < 100; ++i) {
    const std::string ns = "rt/b" + std::to_string(i) + "/";
    for (const char* topic : {"odom", "sonar"}) {
      EXPECT_TRUE(
          peer.wait_endpoint([&](const Endpoint& e) { return e.writer && e.topic == ns + topic; }, kWaitMs))
          << ns << topic;
    }
    EXPECT_TRUE(peer.wait_endpoint([&](const Endpoint& e) { return !e.writer && e.topic == ns + "cmd_vel"; },
                                   kWaitMs))
        << ns << "cmd_vel";
  }
  // A ring of 8 sonars, 1 m long (swarm100.world): one Range per transducer.
  std::set<std::string> frames;
  Range r;
  for (int waited = 0; waited < kWaitMs && frames.size() < 8; waited += 100) {
    if (!take(sonar, r, 100)) continue;
    frames.insert(r.header().frame_id());
    EXPECT_EQ(r.radiation_type(), 0);
    EXPECT_FLOAT_EQ(r.max_range(), 1.0f);
    EXPECT_TRUE(r.range() <= 1.0f || std::isinf(r.range()));
  }
  EXPECT_EQ(frames.size(), 8u);
  EXPECT_EQ(frames.count("b42/sonar_0"), 1u);
  EXPECT_EQ(frames.count("b42/sonar_7"), 1u);
}

// boards/desktop/nodes/ros2.json as it is, but for this test's ports and the
// map file's place.
std::string desktop_config(uint16_t sim_port) {
  std::string text = read_text(std::string(TROUPE_SOURCE_DIR) + "/boards/desktop/nodes/ros2.json");
  auto replace = [&](const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  };
  replace("\"port\": 7000", "\"port\": " + std::to_string(sim_port));
  replace("\"port\": 6666", "\"port\": 0");
  replace("\"examples/", "\"" + std::string(TROUPE_SOURCE_DIR) + "/examples/");
  return text;
}

TEST_F(BridgeTest, TheDesktopExampleBridgesItsLocalizerAndMapAndTakesInitialPose) {
  start_sim("office.world", {"--no-ctrl"});
  const std::string config = dir_ + "/ros2.json";
  std::ofstream(config) << desktop_config(sim_port_);
  // The driver's domain: ROS_DOMAIN_ID, as for any ROS 2 program.
  setenv("ROS_DOMAIN_ID", std::to_string(domain_.id()).c_str(), 1);
  std::string error;
  ASSERT_TRUE(bridge_.start_logged({kBin + "/troupe-node", config}, dir_ + "/node.log", error)) << error;
  ASSERT_TRUE(
      bridge_.wait_for("ros2: 4 devices on DDS domain " + std::to_string(domain_.id()), true, kWaitMs));

  FastDdsPeer peer(domain_.id());
  ASSERT_TRUE(peer.ok());
  const std::string pose_type =
      peer.register_type<geometry_msgs::msg::dds_::PoseWithCovarianceStamped_PubSubType>();
  fdds::DataReader* amcl = peer.reader("rt/amcl_pose", pose_type, kLatched);
  fdds::DataWriter* initial = peer.writer("rt/initialpose", pose_type, kReliable);
  fdds::DataReader* map =
      peer.reader("rt/map", peer.register_type<nav_msgs::msg::dds_::OccupancyGrid_PubSubType>(), kLatched);
  ASSERT_TRUE(amcl && initial && map && wait_matched(initial));

  OccupancyGrid grid;
  ASSERT_TRUE(take(map, grid, kWaitMs));
  EXPECT_EQ(grid.info().width(), 400u) << "office.png: 20 m at 5 cm";
  EXPECT_EQ(grid.info().height(), 300u);
  EXPECT_NEAR(grid.info().origin().position().x(), -10.0, 1e-6);

  PoseWithCovarianceStamped estimate;
  ASSERT_TRUE(take(amcl, estimate, kWaitMs)) << "mcl's estimate on amcl_pose";
  EXPECT_EQ(estimate.header().frame_id(), "map");
  const troupe::client::Pose2 truth = ground_truth();
  EXPECT_NEAR(estimate.pose().pose().position().x(), truth.x, 0.5);
  EXPECT_NEAR(estimate.pose().pose().position().y(), truth.y, 0.5);

  // A pose in another frame is refused; one in the map frame reaches mcl,
  // whose next estimates start from it (1.5 m from the truth).
  PoseWithCovarianceStamped wrong;
  wrong.header().frame_id("odom");
  wrong.pose().pose().orientation().w(1);
  initial->write(&wrong);
  EXPECT_TRUE(bridge_.wait_for("not the map frame", true, kWaitMs));
  PoseWithCovarianceStamped moved;
  moved.header().frame_id("map");
  moved.pose().pose().position().x(truth.x + 1.5);
  moved.pose().pose().position().y(truth.y);
  moved.pose().pose().orientation().w(1);
  moved.pose().covariance()[0] = moved.pose().covariance()[7] = 0.01;
  moved.pose().covariance()[35] = 0.01;
  initial->write(&moved);
  bool followed = false;
  for (int waited = 0; waited < kWaitMs && !followed; waited += 100) {
    if (take(amcl, estimate, 100))
      followed = std::fabs(estimate.pose().pose().position().x() - (truth.x + 1.5)) < 0.5;
  }
  EXPECT_TRUE(followed) << "amcl_pose did not move to the initial pose given";
}

}  // namespace
