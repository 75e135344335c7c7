// SITL with the robot's own binary: the pioneer-p3dx board's troupe-node,
// cross-built for armhf and run under qemu-arm, drives robot r0 of
// sitl_room.world through troupe-sim's emulated Pioneer and SICK LMS200.
// The board reads binary node configs only: the test writes the config as
// JSON and compiles it with flatc against that build's config schema, as
// the board's build does with its own configs.
#include <gtest/gtest.h>

#include <cstdio>

#include "tests/cross/qemu_node.h"
#include "tests/device_harness/device_harness.h"
#include "tests/sitl/sitl_rig.h"

namespace troupe::sitl {
namespace {

constexpr int kWaitMs = 120000;  // qemu-user on a loaded machine

bool write_text(const std::string& path, const std::string& text) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) return false;
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  return std::fclose(f) == 0 && ok;
}

TEST(SitlArmhf, PioneerBoardUnderQemuDrivesTheSimulatedPioneer) {
  cross::CrossBuild build;
  std::string why;
  if (!cross::load_cross_build("pioneer-p3dx-armhf", build, why)) {
    GTEST_SKIP() << why;
  }
  testing::TempDir dir;
  SimRig rig;
  std::string error;
  ASSERT_TRUE(rig.start(dir.path(), error)) << error;

  const std::string json = dir.file("sitl-pioneer.json");
  ASSERT_TRUE(write_text(json, node_config_json(rig)));
  const std::string src = TROUPE_SOURCE_DIR;
  std::string out;
  const int compiled =
      cross::run(cross::quote(TROUPE_FLATC) + " -b -I " + cross::quote(build.path("generated/runtime")) +
                     " -I " + cross::quote(src + "/drivers/p2os") + " -I " +
                     cross::quote(src + "/drivers/sicklms200") + " -o " + cross::quote(dir.path()) + " " +
                     cross::quote(src + "/runtime/config.fbs") + " " + cross::quote(json) + " 2>&1",
                 out);
  ASSERT_EQ(compiled, 0) << out;

  cross::QemuNode node;
  ASSERT_TRUE(node.start(build, build.node, dir.file("sitl-pioneer.bin"), error)) << error;
  auto logs = [&] { return "troupe-node (armhf):\n" + node.log() + "troupe-sim:\n" + rig.sim.err(); };
  ASSERT_TRUE(node.wait_for_log("p2os: connected to r0 (Pioneer p3dx-sh)", 1, kWaitMs)) << logs();
  ASSERT_TRUE(node.wait_for_log("sicklms200: scanner on", 1, kWaitMs)) << logs();

  drive_simulated_pioneer(node.port(), rig.port, logs);

  EXPECT_EQ(node.stop(), 0) << logs();
  EXPECT_EQ(rig.sim.stop(), 0) << logs();
}

}  // namespace
}  // namespace troupe::sitl
