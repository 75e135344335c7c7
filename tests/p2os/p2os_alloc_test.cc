// The p2os driver allocates nothing per SIP once connected: packets in,
// odometry, four devices published, velocity and keep-alives out. Every
// allocation in this program is counted (operator new is replaced); the
// emulator, the node and the client share the one thread, so the count
// over the measured window covers them all.
#include <cstdlib>
#include <new>

#include "tests/p2os/p2os_fixture.h"

namespace {
uint64_t g_allocations = 0;
}

// The replacements below pair malloc with free on purpose; GCC, seeing a
// new-expression inlined next to them, takes them for a mismatch.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  return operator new(n);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}

namespace troupe::testing {
namespace {

TEST_F(P2osNode, SteadyStateAllocatesNothing) {
  start();
  connect();
  client_.send_vel(kBase, 0.3f, 0.2f);
  ASSERT_TRUE(loop_.run_until([&] { return client_.count(kSonar) > 0 && robot_->left_mps() > 0.1; }, 10));
  loop_.run_for(1.0);  // warm: every buffer has met its largest message
  uint32_t sips = robot_->sips_sent(), published = client_.count(kBase);
  uint64_t before = g_allocations;
  loop_.run_for(2.0);
  uint64_t during = g_allocations - before;
  EXPECT_GT(robot_->sips_sent(), sips + 10);
  EXPECT_GT(client_.count(kBase), published + 10);
  EXPECT_EQ(during, 0u);
}

}  // namespace
}  // namespace troupe::testing
