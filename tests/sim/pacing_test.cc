// The one paced loop: flat out it steps until done, answering the network
// between steps without waiting; paused it only serves, waiting at most
// kMaxWaitUs; a step request's speed change or a stop takes effect at once.
#include <gtest/gtest.h>

#include <atomic>
#include <vector>

#include "host-sim/sim_control/pacing.h"

namespace troupe::sim {
namespace {

struct FakeSim {
  double time_s = 0;
  int steps = 0;
  std::vector<int64_t> waits;
  LoopParts parts(double quit_s) {
    LoopParts p;
    p.time_s = [this] { return time_s; };
    p.serve = [this](int64_t wait_us) { waits.push_back(wait_us); };
    p.step = [this] {
      time_s += 0.1;
      ++steps;
    };
    p.done = [this, quit_s] { return time_s + 1e-9 >= quit_s; };
    return p;
  }
};

TEST(Pacing, FlatOutStepsUntilDoneServingBetweenSteps) {
  FakeSim sim;
  SimControl control;
  control.speed = 0;
  std::atomic<bool> stop{false};
  RateMeter rate;
  int after = 0;
  run_paced(control, stop, sim.parts(1.0), rate, [&after] { ++after; });
  EXPECT_EQ(sim.steps, 10);
  EXPECT_EQ(after, 10);
  ASSERT_EQ(sim.waits.size(), 10u);
  for (int64_t w : sim.waits) EXPECT_EQ(w, 0) << "flat out never waits for the network";
}

TEST(Pacing, PausedOnlyServesAndStopsWhenTold) {
  FakeSim sim;
  SimControl control;
  control.paused = true;
  std::atomic<bool> stop{false};
  LoopParts parts = sim.parts(100);
  int polls = 0;
  parts.serve = [&](int64_t wait_us) {
    sim.waits.push_back(wait_us);
    if (++polls == 3) stop = true;  // e.g. a signal while paused
  };
  RateMeter rate;
  run_paced(control, stop, parts, rate);
  EXPECT_EQ(sim.steps, 0);
  EXPECT_EQ(sim.waits, (std::vector<int64_t>{kMaxWaitUs, kMaxWaitUs, kMaxWaitUs}));
}

TEST(Pacing, AResumeFromServeStepsTheSameLoop) {
  FakeSim sim;
  SimControl control;
  control.paused = true;
  std::atomic<bool> stop{false};
  LoopParts parts = sim.parts(0.5);
  parts.serve = [&](int64_t) {
    control.paused = false;  // a Resume request arrived
    control.speed = 0;
  };
  RateMeter rate;
  run_paced(control, stop, parts, rate);
  EXPECT_EQ(sim.steps, 5);
}

TEST(RateMeter, MeasuresOverASecondAndRestartsAfterAReset) {
  SimControl control;
  RateMeter rate;
  rate.update(control, 0.0, 1'000'000);
  rate.update(control, 5.0, 1'500'000);
  EXPECT_EQ(control.real_time_factor, 0) << "not yet a second";
  rate.update(control, 10.0, 2'000'000);
  EXPECT_DOUBLE_EQ(control.real_time_factor, 10.0);
  rate.update(control, 1.0, 2'100'000);  // reset: the clock went back
  rate.update(control, 3.0, 3'100'000);
  EXPECT_DOUBLE_EQ(control.real_time_factor, 2.0);
}

}  // namespace
}  // namespace troupe::sim
