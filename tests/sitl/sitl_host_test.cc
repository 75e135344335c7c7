// SITL on the host: troupe-sim presents robot r0 as a Pioneer and a SICK
// LMS200 on pseudo-terminals; the host's troupe-node, with its real p2os
// and sicklms200 drivers, drives it; a client checks that odometry, laser
// and sonar agree with the simulated world.
#include <gtest/gtest.h>

#include <cstdio>

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
  ASSERT_TRUE(rig.start(dir.path(), error)) << error;

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
  EXPECT_EQ(rig.sim.stop(), 0) << logs();
}

}  // namespace
}  // namespace troupe::sitl
