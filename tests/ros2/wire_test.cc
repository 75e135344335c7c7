// The bridge's traffic as Wireshark reads it: tshark captures loopback while
// troupe-ros2 and a Fast DDS peer discover each other, and its RTPS dissector
// must find ROS 2's topic and type names, and the type hash, in the
// discovery data. Capturing needs root (or dumpcap's capabilities); without
// either the test says so and skips.
#include <unistd.h>

#include <set>
#include <sstream>
#include <vector>

#include "tests/ros2/bridge_fixture.h"

namespace {

using namespace troupe::testing;
using namespace troupe::testing::ros2;

std::string hex_of(const std::string& text) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (unsigned char c : text) {
    out += digits[c >> 4];
    out += digits[c & 15];
  }
  return out;
}

TEST_F(BridgeTest, TsharkFindsRos2TopicAndTypeNamesOnTheWire) {
  if (access("/usr/bin/tshark", X_OK) != 0)
    GTEST_SKIP() << "tshark is missing (Debian: apt-get install tshark)";
  // Only this test's domain: its 250 ports.
  const int base = 7400 + 250 * domain_.id();
  const std::string capture = dir_ + "/bridge.pcapng";
  ChildProcess tshark;
  std::string error;
  ASSERT_TRUE(tshark.start(
      {"tshark", "-i", "lo", "-f", "udp portrange " + std::to_string(base) + "-" + std::to_string(base + 249),
       "-w", capture},
      dir_, "tshark", error))
      << error;
  if (!tshark.wait_for("Capturing on", true, kWaitMs)) {
    GTEST_SKIP() << "tshark cannot capture on loopback here (root needed): " << tshark.err();
  }

  start_sim("room.world");
  start_bridge();
  FastDdsPeer peer(domain_.id());
  ASSERT_TRUE(peer.ok());
  fdds::DataReader* scans = peer.reader(
      "rt/r0/scan", peer.register_type<sensor_msgs::msg::dds_::LaserScan_PubSubType>(), kSensorQos);
  LaserScan s;
  ASSERT_TRUE(take(scans, s, kWaitMs));
  const std::pair<std::string, std::string> want[] = {
      {"rt/r0/scan", "sensor_msgs::msg::dds_::LaserScan_"},
      {"rt/r0/odom", "nav_msgs::msg::dds_::Odometry_"},
      {"rt/r0/cmd_vel", "geometry_msgs::msg::dds_::Twist_"},
      {"rt/tf", "tf2_msgs::msg::dds_::TFMessage_"},
      {"rt/clock", "rosgraph_msgs::msg::dds_::Clock_"},
      {"ros_discovery_info", "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_"},
  };
  // Everything discovered has crossed the wire, then (and the capture holds it).
  for (const auto& w : want) {
    EXPECT_TRUE(peer.wait_endpoint([&](const Endpoint& e) { return e.topic == w.first; }, kWaitMs))
        << w.first;
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  tshark.stop();

  const ProgramResult r =
      run_to_end({"tshark", "-r", capture, "-Y", "rtps", "-T", "fields", "-e", "rtps.param.topicName", "-e",
                  "rtps.param.typeName", "-e", "rtps.param.userData"},
                 60000);
  ASSERT_EQ(r.status, 0) << r.err;
  std::set<std::pair<std::string, std::string>> names;
  std::string user_data;
  // One line a packet; a packet with several discovery samples lists their
  // values in order, separated by commas.
  auto split = [](const std::string& field) {
    std::vector<std::string> parts;
    std::istringstream in(field);
    for (std::string p; std::getline(in, p, ',');) parts.push_back(p);
    return parts;
  };
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    std::string topics, types, data;
    std::getline(fields, topics, '\t');
    std::getline(fields, types, '\t');
    std::getline(fields, data, '\t');
    const auto topic = split(topics), type = split(types);
    for (size_t i = 0; i < topic.size() && i < type.size(); ++i) names.insert({topic[i], type[i]});
    user_data += data;
  }
  for (const auto& w : want)
    EXPECT_EQ(names.count(w), 1u) << w.first << " " << w.second << " not in the capture";
  // The scan writer's user data, as the dissector shows the bytes.
  std::string digits;
  for (char c : user_data) {
    if (std::isxdigit(static_cast<unsigned char>(c)))
      digits += char(std::tolower(static_cast<unsigned char>(c)));
  }
  EXPECT_NE(digits.find(
                hex_of("typehash=RIHS01_64c191398013af96509d518dac71d5164f9382553fce5c1f8cca5be7924bd828;")),
            std::string::npos);
}

}  // namespace
