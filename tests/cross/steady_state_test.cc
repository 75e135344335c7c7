// Steady state on the target: a troupe-node cross-built for powerpc and
// armhf, run under qemu-user, serves a client for 100,000 messages while a
// counting allocator preloaded into it watches the heap. The heap must not
// grow, and serving must not allocate at all.
#include <gtest/gtest.h>
#include <signal.h>

#include <cstdio>
#include <cstdlib>

#include "tests/cross/qemu_node.h"
#include "wire/client/client.h"

namespace troupe::cross {
namespace {

const wire::Address kBase(0, uint16_t(wire::Interface::Position2d), 0);
constexpr long kMessages = 100000;

struct HeapReport {
  long long allocations = -1, frees = -1, live_bytes = -1;
};

// The `n`th (0-based) "alloc-count:" line of the node's log.
HeapReport parse_report(const std::string& log, int n) {
  HeapReport r;
  size_t at = std::string::npos;
  for (int i = 0; i <= n; ++i) {
    at = log.find("alloc-count:", at == std::string::npos ? 0 : at + 1);
    if (at == std::string::npos) return r;
  }
  sscanf(log.c_str() + at, "alloc-count: allocations=%lld frees=%lld live_bytes=%lld", &r.allocations,
         &r.frees, &r.live_bytes);
  return r;
}

long rss_kib(pid_t pid) {
  std::string status = read_text("/proc/" + std::to_string(pid) + "/status");
  size_t at = status.find("VmRSS:");
  return at == std::string::npos ? -1 : atol(status.c_str() + at + 6);
}

class SteadyState : public ::testing::TestWithParam<const char*> {
 protected:
  // `iterations` rounds of: a velocity command, then a Pull answered by the
  // newest data and an Ack. Returns the messages exchanged (sent and
  // received), or -1 when the node stopped answering.
  long serve(client::Client& c, int iterations) {
    long before = data_seen_;
    for (int i = 0; i < iterations; ++i) {
      auto& b = c.begin();
      wire::Pose2d vel(i % 2 ? 0.1f : -0.1f, 0, 0);
      auto body = wire::CreatePosition2dVel(b, &vel);
      if (!c.command(kBase, uint8_t(wire::Position2dCmdSub::Vel), wire::Body::Position2dVel, body.Union()))
        return -1;
      if (!c.pull(kBase)) return -1;
    }
    return 3L * iterations + (data_seen_ - before);  // command, pull, ack; data
  }

  HeapReport report(int n) {
    node_.signal(SIGUSR1);
    if (!node_.wait_for_log("alloc-count:", n + 1)) return {};
    return parse_report(node_.log(), n);
  }

  CrossBuild build_;
  QemuNode node_;
  long data_seen_ = 0;
};

TEST_P(SteadyState, ServesHundredThousandMessagesWithoutHeapGrowth) {
  std::string why;
  if (!load_cross_build(GetParam(), build_, why)) {
    GTEST_SKIP() << why;
  }
  QemuNode::Extras counted;
  counted.preload = build_.path("tests/cross/target/libtroupe_alloc_count.so");
  std::string error;
  ASSERT_TRUE(node_.start(build_, build_.node, build_.path("configs/ppc-node.bin"), error, counted)) << error;
  client::Client::Options options;
  options.reconnect = false;
  client::Client c("127.0.0.1", node_.port(), options);
  ASSERT_TRUE(c.connect()) << c.error();
  c.add_data_handler([this](const wire::Message&) { ++data_seen_; });
  ASSERT_TRUE(c.open(kBase, wire::Access::All, wire::Delivery::Pull)) << c.error();

  // Warm up: buffers take the sizes this traffic needs. Pulls are answered
  // with data only once the driver published (its first publication sizes
  // the node's message builder and the device's data slot), which may be
  // after many round trips: warm up until data came back.
  ASSERT_GT(serve(c, 1000), 0) << c.error();
  for (int i = 0; i < 1000 && data_seen_ == 0; ++i) {
    ASSERT_GT(serve(c, 10), 0) << c.error();
  }
  ASSERT_GT(data_seen_, 0) << "the kinematic driver never published";
  HeapReport before = report(0);
  ASSERT_GE(before.allocations, 0) << "no report from the preloaded counter:\n" << node_.log();
  long rss_before = rss_kib(node_.pid());

  long messages = 0;
  while (messages < kMessages) {
    long n = serve(c, 1000);
    ASSERT_GT(n, 0) << c.error();
    messages += n;
  }
  HeapReport after = report(1);
  ASSERT_GE(after.allocations, 0) << node_.log();
  long rss_after = rss_kib(node_.pid());

  printf(
      "%s: %ld messages; allocations %lld, frees %lld, live heap %lld -> %lld bytes; qemu RSS %ld -> %ld "
      "KiB\n",
      GetParam(), messages, after.allocations - before.allocations, after.frees - before.frees,
      before.live_bytes, after.live_bytes, rss_before, rss_after);
  EXPECT_EQ(after.live_bytes, before.live_bytes);
  EXPECT_EQ(after.allocations - before.allocations, 0) << "serving allocated";
  EXPECT_EQ(node_.stop(), 0) << node_.log();
}

INSTANTIATE_TEST_SUITE_P(Targets, SteadyState, ::testing::Values("ppc-node-powerpc", "ppc-node-armhf"),
                         [](const auto& param_info) {
                           std::string name = param_info.param;
                           return name.substr(name.rfind('-') + 1);
                         });

}  // namespace
}  // namespace troupe::cross
