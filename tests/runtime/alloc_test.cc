// The node allocates nothing per message once warm: commands in, requests
// and replies, data out to a reader. Every allocation of the node's thread
// is counted by replacing operator new in this program.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <thread>

#include "tests/runtime/node_fixture.h"
#include "wire/client/proxies.h"

namespace {
thread_local uint64_t t_allocations = 0;
}

void* operator new(std::size_t n) {
  ++t_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace troupe::testing {
namespace {

using wire::Interface;

TEST(Allocation, SteadyStateAllocatesNothingPerMessage) {
  Node node(test_options());
  auto* base = new Recorder;
  auto* laser = new Recorder;
  DeviceId base_id = node.add_device(addr(Interface::Position2d), base, "base");
  DeviceId laser_id = node.add_device(addr(Interface::Ranger), laser, "laser");
  std::string error;
  DeviceId one[1] = {base_id}, two[1] = {laser_id};
  DriverSetup s1, s2;
  s1.provides = one;
  s2.provides = two;
  ASSERT_TRUE(node.add_driver(std::unique_ptr<Driver>(base), s1, error)) << error;
  ASSERT_TRUE(node.add_driver(std::unique_ptr<Driver>(laser), s2, error)) << error;
  ASSERT_TRUE(node.start(error)) << error;

  constexpr int kWarmup = 500, kMeasured = 5000;
  std::atomic<int> done{0};
  std::atomic<bool> failed{false};
  std::thread traffic([&, port = node.port()] {
    client::Client c("127.0.0.1", port);
    if (!c.connect()) return failed.store(true);
    client::RangerProxy scans(c);
    client::Position2dProxy pos(c);
    for (int i = 0; i < kWarmup + kMeasured; ++i) {
      pos.set_velocity(0.001f * float(i % 100), 0, 0);  // a command
      laser->burst(1);                                   // a data message out
      client::Reply r = c.request(addr(Interface::Position2d), 4);  // a request and its Ack
      if (!r.ok()) return failed.store(true);
      done.store(i + 1);
    }
  });
  while (done.load() < kWarmup && !failed.load()) node.poll(1000);
  uint64_t before = t_allocations;
  while (done.load() < kWarmup + kMeasured && !failed.load()) node.poll(1000);
  uint64_t during = t_allocations - before;
  traffic.join();
  // The last burst may still be waiting in the node's loop.
  for (int i = 0; i < 100 && laser->published.load() < uint32_t(kWarmup + kMeasured); ++i) node.poll(1000);
  ASSERT_FALSE(failed.load());
  EXPECT_EQ(during, 0u) << "allocations by the node over " << kMeasured << " commands, requests and data";
  EXPECT_GE(base->commands.load(), 1);
  EXPECT_GE(laser->published.load(), uint32_t(kWarmup + kMeasured));
  node.shutdown();
}

}  // namespace
}  // namespace troupe::testing
