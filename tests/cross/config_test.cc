// A board's compiled config changed on the robot: troupe-node --set and
// --print-config cross-built (big-endian powerpc, armhf) under qemu-user,
// against what the host's node makes of the JSON; and `troupe config
// compile` against the board build's own compiled config.
#include <gtest/gtest.h>

#include "tests/cross/qemu_node.h"

namespace troupe::cross {
namespace {

const std::string kHostBin = std::string(TROUPE_BINARY_DIR) + "/bin";
const std::string kJson = std::string(TROUPE_SOURCE_DIR) + "/boards/ppc-node/nodes/ppc-node.json";

class BoardConfig : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    if (!load_cross_build(GetParam(), build_, skip_)) GTEST_SKIP() << skip_;
  }
  CrossBuild build_;
  std::string skip_;
};

TEST_P(BoardConfig, SetAndPrintConfigOnTheTargetGiveWhatTheHostGives) {
  const std::vector<std::string> sets = {"--set", "kinematic.max_speed=0.25", "--set",  "name=lab-base",
                                         "--set", "kinematic.initial_x=-1.5", "--port", "7003"};
  std::vector<std::string> args = {build_.path("configs/ppc-node.bin")};
  args.insert(args.end(), sets.begin(), sets.end());
  args.push_back("--print-config");
  std::string on_target, on_host;
  ASSERT_EQ(run(qemu_command(build_, build_.node, args), on_target), 0) << on_target;
  std::string host = quote(kHostBin + "/troupe-node") + " " + quote(kJson);
  for (const std::string& s : sets) host += " " + quote(s);
  ASSERT_EQ(run(host + " --print-config", on_host), 0) << on_host;
  EXPECT_EQ(on_target, on_host);
  EXPECT_NE(on_target.find("\"max_speed\": 0.25"), std::string::npos) << on_target;
  EXPECT_NE(on_target.find("\"initial_x\": -1.5"), std::string::npos) << on_target;

  // A mistake is one on the target too: exit 2, nothing printed.
  std::string out;
  EXPECT_EQ(run(qemu_command(build_, build_.node,
                             {build_.path("configs/ppc-node.bin"), "--set", "kinematic.max_sped=1",
                              "--print-config"}) +
                    " 2>/dev/null",
                out),
            2);
  EXPECT_EQ(out, "");
}

TEST_P(BoardConfig, TroupeConfigCompileMakesWhatTheBoardBuildMakes) {
  const std::string bin = make_temp_dir("config") + "/ppc-node.bin";
  std::string out;
  ASSERT_EQ(run(quote(kHostBin + "/troupe") + " config compile " + quote(kJson) + " --board ppc-node -o " +
                    quote(bin),
                out),
            0);
  EXPECT_EQ(read_text(bin), read_text(build_.path("configs/ppc-node.bin")));
}

INSTANTIATE_TEST_SUITE_P(Targets, BoardConfig, ::testing::Values("ppc-node-powerpc", "ppc-node-armhf"),
                         [](const auto& param_info) { return test_name_of(param_info.param); });

}  // namespace
}  // namespace troupe::cross
