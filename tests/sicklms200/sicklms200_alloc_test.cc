// The sicklms200 driver allocates nothing per scan once streaming. Every
// allocation in this program is counted (operator new is replaced); the
// emulator, the node and the client share the one thread.
#include <cstdlib>
#include <new>

#include "tests/sicklms200/sick_fixture.h"

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

TEST_F(SickNode, SteadyStateAllocatesNothing) {
  start({}, R"("resolution_cdeg": 50, "baud": 500000)");
  ASSERT_TRUE(streaming());
  loop_.run_for(0.5);
  uint32_t scans = client_.count(kLaser);
  uint64_t before = g_allocations;
  loop_.run_for(2.0);
  uint64_t during = g_allocations - before;
  EXPECT_GT(client_.count(kLaser), scans + 20);
  EXPECT_EQ(during, 0u);
  EXPECT_EQ(mismatched_, 0u);
}

}  // namespace
}  // namespace troupe::testing
