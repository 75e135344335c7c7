// The serial drivers allocate nothing per message once connected: p2os per
// SIP (packets in, odometry, four devices published, velocity and
// keep-alives out), sicklms200 per scan. Every allocation in this program
// is counted (operator new is replaced); the emulator, the node and the
// client share the one thread, so the count over the measured window
// covers them all. One test, parameterised over the driver.
#include <cstdlib>
#include <memory>
#include <new>

#include "tests/p2os/p2os_fixture.h"
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

// One driver against its emulator: brought to its steady state, then run
// while allocations are counted.
class DriverCase {
 public:
  virtual ~DriverCase() = default;
  /// Connects and warms every buffer up to its largest message.
  virtual void warm() = 0;
  virtual Loop& loop() = 0;
  /// Messages that flowed so far, to show the window was not idle.
  virtual uint32_t messages() const = 0;
  /// What the client got is what the device sent.
  virtual bool consistent() const { return true; }
};

class P2osCase final : public DriverCase, P2osRig {
 public:
  void warm() override {
    start();
    connect();
    client_.send_vel(kBase, 0.3f, 0.2f);
    ASSERT_TRUE(loop_.run_until([&] { return client_.count(kSonar) > 0 && robot_->left_mps() > 0.1; }, 10));
    loop_.run_for(1.0);
  }
  Loop& loop() override { return loop_; }
  uint32_t messages() const override { return robot_->sips_sent() + client_.count(kBase); }
};

class SickCase final : public DriverCase, SickRig {
 public:
  void warm() override {
    start({}, R"("resolution_cdeg": 50, "baud": 500000)");
    ASSERT_TRUE(streaming());
    loop_.run_for(0.5);
  }
  Loop& loop() override { return loop_; }
  uint32_t messages() const override { return client_.count(kLaser); }
  bool consistent() const override { return mismatched_ == 0; }
};

class SteadyState : public ::testing::TestWithParam<const char*> {};

TEST_P(SteadyState, AllocatesNothing) {
  std::unique_ptr<DriverCase> driver;
  if (std::string(GetParam()) == "p2os") driver = std::make_unique<P2osCase>();
  else driver = std::make_unique<SickCase>();
  driver->warm();
  if (HasFatalFailure()) return;
  uint32_t before_messages = driver->messages();
  uint64_t before = g_allocations;
  driver->loop().run_for(2.0);
  uint64_t during = g_allocations - before;
  EXPECT_GT(driver->messages(), before_messages + 20);
  EXPECT_EQ(during, 0u);
  EXPECT_TRUE(driver->consistent());
}

INSTANTIATE_TEST_SUITE_P(Drivers, SteadyState, ::testing::Values("p2os", "sicklms200"),
                         [](const ::testing::TestParamInfo<const char*>& p) { return std::string(p.param); });

}  // namespace
}  // namespace troupe::testing
