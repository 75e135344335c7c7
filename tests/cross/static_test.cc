// Self-contained board binaries (TROUPE_STATIC): the node of ppc-node
// (a kinematic base), linked fully statically for armhf, arm64 and
// big-endian powerpc, runs under qemu-user in a root that holds no file of
// the target at all, and an x86 client drives its base.
//
// The root: qemu-user's -L names the folder it looks in first for the
// program's loader and for every file the program opens by an absolute
// path; an empty folder there leaves the target nothing but the host's
// files, none of which are of its architecture. The dynamic build of each
// target is the control: in the same root it cannot even start.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/cross/qemu_node.h"
#include "wire/client/proxies.h"

namespace troupe::cross {
namespace {

constexpr int kWaitMs = 20000;  // bounds a wait against hangs, not speed

struct Target {
  const char* static_build;
  const char* dynamic_build;  // of the same target, for the control
};

class StaticNode : public ::testing::TestWithParam<Target> {
 protected:
  void SetUp() override {
    std::string why;
    if (!load_cross_build(GetParam().static_build, b_, why)) {
      GTEST_SKIP() << why;
    }
    empty_root_ = make_temp_dir("empty-root-" + b_.name);
    ASSERT_FALSE(empty_root_.empty());
  }
  void TearDown() override {
    std::string ignored;
    if (!empty_root_.empty()) run("rmdir " + quote(empty_root_), ignored);  // rmdir: it must still be empty
  }

  // `build` run with the empty root instead of the toolchain's target folder.
  CrossBuild in_empty_root(CrossBuild build) const {
    build.loader_prefix = empty_root_;
    build.sysroot_lib.clear();
    return build;
  }

  CrossBuild b_;
  std::string empty_root_;
};

TEST_P(StaticNode, IsLinkedStatically) {
  ASSERT_TRUE(b_.is_static) << b_.dir << "/board.json";
  std::string out;
  ASSERT_EQ(run(quote(b_.readelf) + " --wide --program-headers --dynamic " + quote(b_.node), out), 0);
  EXPECT_EQ(out.find("INTERP"), std::string::npos) << "a program interpreter (dynamic loader):\n" << out;
  EXPECT_EQ(out.find("(NEEDED)"), std::string::npos) << "needs shared libraries:\n" << out;
}

TEST_P(StaticNode, ServesAndIsDrivenFromARootWithoutTargetLibraries) {
  CrossBuild run_here = in_empty_root(b_);
  QemuNode node;
  std::string error;
  ASSERT_TRUE(node.start(run_here, b_.node, b_.path("configs/ppc-node.bin"), error)) << error;

  client::Client::Options options;
  options.name = "static-test";
  options.reconnect = false;
  client::Client c("127.0.0.1", node.port(), options);
  ASSERT_TRUE(c.connect()) << c.error();
  EXPECT_EQ(c.node_name(), "ppc-node");
  std::vector<client::DeviceEntry> devices;
  ASSERT_TRUE(c.device_list(devices)) << c.error();
  ASSERT_EQ(devices.size(), 1u);
  EXPECT_EQ(devices[0].text(), "position2d:0");

  client::Position2dProxy base(c);
  ASSERT_TRUE(base.is_open()) << c.error();
  ASSERT_TRUE(base.set_velocity(0.3f, 0.0f, 0.0f));
  auto moved = [&] { return std::fabs(base.velocity().x - 0.3f) < 1e-4f && base.x() > 0.05f; };
  for (int waited = 0; waited < kWaitMs && !moved(); waited += 10) c.spin_once(10);
  EXPECT_TRUE(moved()) << "velocity " << base.velocity().x << " m/s, x " << base.x() << " m\n" << node.log();
  EXPECT_EQ(node.stop(), 0) << node.log();
}

TEST_P(StaticNode, TheDynamicNodeCannotStartInTheSameRoot) {
  CrossBuild dynamic;
  if (std::string why; !load_cross_build(GetParam().dynamic_build, dynamic, why)) {
    GTEST_SKIP() << "no control: " << why;
  }
  ASSERT_FALSE(dynamic.is_static);
  // It fails for the reason the static node does not have: its loader
  // (and the target's libc) are not there. (With them, the other cross
  // tests start it.)
  std::string config = dynamic.path("configs/" + dynamic.board + ".bin");
  QemuNode node;
  std::string error;
  EXPECT_FALSE(node.start(in_empty_root(dynamic), dynamic.node, config, error));
  EXPECT_NE(error.find("Could not open '/lib"), std::string::npos) << error;
}

INSTANTIATE_TEST_SUITE_P(Targets, StaticNode,
                         ::testing::Values(Target{"ppc-node-armhf-static", "ppc-node-armhf"},
                                           Target{"ppc-node-arm64-static", "diffbot-can-arm64"},
                                           Target{"ppc-node-powerpc-static", "ppc-node-powerpc"}),
                         [](const auto& param_info) {
                           std::string name = param_info.param.static_build;
                           name = name.substr(name.find('-', 4) + 1);  // "armhf-static"
                           for (char& c : name) {
                             if (c == '-') c = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace troupe::cross
