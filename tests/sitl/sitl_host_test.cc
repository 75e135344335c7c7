// SITL on the host: troupe-sim presents robot r0 as a Pioneer and a SICK
// LMS200 on pseudo-terminals; the host's troupe-node, with its real p2os
// and sicklms200 drivers, drives it; a client checks that odometry, laser
// and sonar agree with the simulated world.
#include <gtest/gtest.h>

#include <cstdio>
#include <utility>
#include <vector>

#include "tests/device_harness/device_harness.h"
#include "tests/sitl/sitl_rig.h"

namespace troupe::sitl {
namespace {

constexpr int kWaitMs = 60000;

bool write_text(const std::string& path, const std::string& text) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) return false;
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  return std::fclose(f) == 0 && ok;
}

TEST(SitlHost, NodeDrivesTheSimulatedPioneer) {
  testing::TempDir dir;
  SimRig rig;
  std::string error;
  // The node opens the devices by their stable names (--emulate-links).
  ASSERT_TRUE(rig.start(dir.path(), error, true)) << error;
  EXPECT_EQ(rig.p2os_path, dir.file("r0-p2os"));
  EXPECT_EQ(rig.sick_path, dir.file("r0-sicklms200"));

  const std::string config = dir.file("sitl-pioneer.json");
  ASSERT_TRUE(write_text(config, node_config_json(rig)));
  ChildProcess node;
  ASSERT_TRUE(node.start({TROUPE_NODE_BIN, config}, dir.path(), "troupe-node", error)) << error;
  auto logs = [&] { return "troupe-node:\n" + node.err() + "troupe-sim:\n" + rig.sim.err(); };
  // Both drivers find their device: the handshake and the scanner's set-up
  // ran over the ptys.
  ASSERT_TRUE(node.wait_for("serving", true, kWaitMs)) << logs();
  ASSERT_TRUE(node.wait_for("p2os: connected to r0 (Pioneer p3dx-sh)", true, kWaitMs)) << logs();
  ASSERT_TRUE(node.wait_for("sicklms200: scanner on", true, kWaitMs)) << logs();
  const std::string err = node.err();
  const std::string needle = " on 127.0.0.1:";
  const size_t at = err.find(needle);
  ASSERT_NE(at, std::string::npos) << err;
  const uint16_t port = uint16_t(std::atoi(err.c_str() + at + needle.size()));

  drive_simulated_pioneer(port, rig.port, logs);
  EXPECT_EQ(node.stop(), 0) << logs();

  // The devices outlive their driver, as hardware does: a new node finds
  // the robot again (a session left open, a scanner streaming at 38400 baud).
  ChildProcess again;
  ASSERT_TRUE(again.start({TROUPE_NODE_BIN, config}, dir.path(), "troupe-node-2", error)) << error;
  auto logs2 = [&] { return "troupe-node:\n" + again.err() + "troupe-sim:\n" + rig.sim.err(); };
  EXPECT_TRUE(again.wait_for("p2os: connected to r0 (Pioneer p3dx-sh)", true, kWaitMs)) << logs2();
  EXPECT_TRUE(again.wait_for("sicklms200: scanner on", true, kWaitMs)) << logs2();
  EXPECT_EQ(again.stop(), 0) << logs2();
  EXPECT_EQ(rig.sim.stop(), 0) << logs2();
}

// A spec troupe-sim cannot honour stops it before it serves, saying why.
TEST(SitlHost, BadEmulateSpecStopsTroupeSimSayingWhy) {
  testing::TempDir dir;
  const std::string world = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/sitl_room.world";
  for (const char* spec : {"r7=p2os", "r0=p2os,lidar"}) {
    ChildProcess sim;
    std::string error;
    ASSERT_TRUE(
        sim.start({TROUPE_SIM_BIN, world, "--port", "0", "--emulate", spec}, dir.path(), "sim", error));
    EXPECT_EQ(sim.wait_exit(kWaitMs), 1) << sim.err();
    EXPECT_NE(sim.err().find(std::string("troupe-sim: --emulate ") + spec + ": "), std::string::npos)
        << sim.err();
    EXPECT_EQ(sim.out().find("listening"), std::string::npos) << sim.out();
  }
  // Where the paths cannot be written, likewise.
  const std::string missing = dir.file("no-such-folder");
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--emulate-info", missing + "/info.txt"}, "--emulate-info: cannot write " + missing + "/info.txt"},
      {{"--emulate-links", missing}, "cannot link " + missing + "/r0-p2os"}};
  for (const auto& [extra, message] : cases) {
    std::vector<std::string> argv = {TROUPE_SIM_BIN, world, "--port", "0", "--emulate", "r0=p2os"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    ChildProcess sim;
    std::string error;
    ASSERT_TRUE(sim.start(argv, dir.path(), "sim", error));
    EXPECT_EQ(sim.wait_exit(kWaitMs), 1) << sim.err();
    EXPECT_NE(sim.err().find(message), std::string::npos) << sim.err();
  }
}

}  // namespace
}  // namespace troupe::sitl
