// What only a kernel CAN bus has: receive filters, and an interface that goes
// down or disappears. These run in the vcan VM (TROUPE_TEST_CAN_INTERFACE
// set, see tests/vcan) and are skipped on a socketpair.
#include <gtest/gtest.h>
#include <poll.h>
#include <unistd.h>

#include <cstdlib>
#include <set>

#include "drivers/odrive_can/can_io.h"
#include "drivers/odrive_can/cansimple.h"
#include "tests/odrive/odrive_rig.h"

namespace troupe::testing {
namespace {

using cansimple::AxisState;
using cansimple::Cmd;

std::string kernel_interface() {
  const char* iface = getenv("TROUPE_TEST_CAN_INTERFACE");
  return iface ? iface : "";
}

#define REQUIRE_KERNEL_CAN(iface) \
  if (iface.empty())              \
  GTEST_SKIP() << "needs a kernel CAN interface (the vcan VM test sets TROUPE_TEST_CAN_INTERFACE)"

bool ip(const std::string& args) {
  return system(("ip " + args).c_str()) == 0;
}

bool recovered(OdriveRig& rig) {
  return rig.left().state() == AxisState::ClosedLoopControl &&
         rig.right().state() == AxisState::ClosedLoopControl && !rig.base().stall;
}

TEST(KernelCan, FiltersLetThroughOnlyTheTwoNodesDataFrames) {
  const std::string iface = kernel_interface();
  REQUIRE_KERNEL_CAN(iface);
  std::string error;
  const uint8_t ids[] = {0, 1};
  int filtered = cansimple::open_can_socket(iface, ids, error);
  ASSERT_GE(filtered, 0) << error;
  int sender = cansimple::open_can_socket(iface, {}, error);
  ASSERT_GE(sender, 0) << error;

  can_frame extended = cansimple::heartbeat_frame(0, {});
  extended.can_id |= CAN_EFF_FLAG;
  const can_frame frames[] = {
      cansimple::heartbeat_frame(0, {}),                          // node 0: in
      cansimple::heartbeat_frame(2, {}),                          // node 2: out
      cansimple::get_request_frame(1, Cmd::GetEncoderEstimates),  // a remote frame: out
      extended,                                                   // an extended id: out
      cansimple::encoder_estimates_frame(1, {1, 2}),              // node 1: in
      cansimple::set_input_vel_frame(0x21, {1, 0}),               // node 33: out
  };
  int err = 0;
  for (const can_frame& f : frames)
    ASSERT_EQ(cansimple::write_frame(sender, f, err), cansimple::IoResult::Frame);

  std::set<uint32_t> seen;
  pollfd p{filtered, POLLIN, 0};
  while (poll(&p, 1, 200) > 0) {
    can_frame f;
    while (cansimple::read_frame(filtered, f, err) == cansimple::IoResult::Frame) seen.insert(f.can_id);
  }
  EXPECT_EQ(seen, (std::set<uint32_t>{cansimple::make_id(0, Cmd::Heartbeat),
                                      cansimple::make_id(1, Cmd::GetEncoderEstimates)}));
  close(filtered);
  close(sender);
}

TEST(KernelCan, InterfaceDownStopsTheBaseAndUpRecovers) {
  const std::string iface = kernel_interface();
  REQUIRE_KERNEL_CAN(iface);
  OdriveRig rig;
  ASSERT_EQ(rig.error(), "");
  ASSERT_TRUE(rig.run_until([&] { return recovered(rig); }, 5));
  rig.client.command_vel(OdriveRig::kBase, 0.3f, 0);
  rig.run_for(0.3);
  ASSERT_TRUE(ip("link set " + iface + " down"));
  ASSERT_TRUE(rig.run_until([&] { return rig.base().stall; }, 3));
  EXPECT_FALSE(rig.base().fault.empty());
  rig.run_for(1.0);  // the emulated axes hear nothing: their watchdogs disarm them
  EXPECT_EQ(rig.left().state(), AxisState::Idle);
  ASSERT_TRUE(ip("link set " + iface + " up"));
  ASSERT_TRUE(rig.run_until([&] { return recovered(rig); }, 10)) << rig.base().fault;
  ASSERT_TRUE(rig.run_until([&] { return rig.left().velocity() > 0.5f; }, 3));
}

TEST(KernelCan, InterfaceRemovedAndCreatedAgainIsReopened) {
  const std::string iface = kernel_interface();
  REQUIRE_KERNEL_CAN(iface);
  OdriveRig rig;
  ASSERT_EQ(rig.error(), "");
  ASSERT_TRUE(rig.run_until([&] { return recovered(rig); }, 5));
  ASSERT_TRUE(ip("link del " + iface));
  ASSERT_TRUE(rig.run_until([&] { return rig.base().stall; }, 3));
  rig.run_for(0.5);
  ASSERT_TRUE(ip("link add dev " + iface + " type vcan") && ip("link set up " + iface));
  std::string error;
  ASSERT_TRUE(rig.restart_emulator(error)) << error;  // the emulator's socket went with the interface
  // The driver reopens the interface with backoff and re-arms the axes.
  ASSERT_TRUE(rig.run_until([&] { return recovered(rig); }, 15)) << rig.base().fault;
}

}  // namespace
}  // namespace troupe::testing
