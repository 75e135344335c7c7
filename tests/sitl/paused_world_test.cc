// Stage's `paused 1`, as Stage reads it: honoured only where someone can
// resume the simulation. troupe-sim run as a user runs it, on a world that
// says `paused 1`: headless (--no-serve) it runs to its quit time and says
// it ignored the line; served it waits, says how to resume, and a client's
// resume lets it run to its end.
#include <gtest/gtest.h>

#include <fstream>

#include "tests/support/child_process.h"
#include "wire/client/proxies.h"

namespace troupe::testing {
namespace {

constexpr int kWaitMs = 60000;  // a bound against hangs, not a measurement

class PausedWorld : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = make_temp_dir("paused-world");
    world_ = dir_ + "/paused.world";
    std::ofstream(world_) << "# a Stage world saved from its GUI while paused\n"
                             "interval_sim 100\n"
                             "paused 1\n"
                             "position ( name \"r0\" pose [ 0 0 0 0 ] )\n";
  }
  void TearDown() override { remove_tree(dir_); }

  std::string dir_, world_;
};

TEST_F(PausedWorld, HeadlessRunsItToTheEnd) {
  ProgramResult run = run_to_end({TROUPE_SIM_BIN, world_, "--no-serve", "--fast", "--quit-time", "5"}, kWaitMs);
  EXPECT_EQ(run.status, 0) << run.out << run.err;
  EXPECT_NE(run.err.find(world_ + ":3: the world says paused; a headless run (--no-serve) ignores it"),
            std::string::npos)
      << run.err;
}

TEST_F(PausedWorld, PausedOnTheCommandLineWithoutServingIsRefused) {
  ProgramResult run = run_to_end({TROUPE_SIM_BIN, world_, "--no-serve", "--paused"}, kWaitMs);
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("nothing could ever resume"), std::string::npos) << run.err;
}

TEST_F(PausedWorld, ServedItWaitsForAClientToResume) {
  ChildProcess sim;
  std::string error;
  ASSERT_TRUE(sim.start({TROUPE_SIM_BIN, world_, "--port", "0", "--no-view", "--fast", "--quit-time", "5"}, dir_,
                        "troupe-sim", error))
      << error;
  ASSERT_TRUE(sim.wait_for("listening on 127.0.0.1:", false, kWaitMs)) << sim.out() << sim.err();
  ASSERT_TRUE(sim.wait_for(world_ + ":3: the world starts paused; resume it with `troupe req", true, kWaitMs))
      << sim.err();
  const std::string out = sim.out();
  const uint16_t port = uint16_t(std::stoi(out.substr(out.find("listening on 127.0.0.1:") + 23)));
  client::Client::Options o;
  o.name = "paused-test";
  o.reconnect = false;
  client::Client c("127.0.0.1", port, o);
  ASSERT_TRUE(c.connect()) << c.error();
  client::SimulationProxy simulation(c);
  // Still at time 0 and paused, however long it has been up (pausing a
  // paused simulation answers with its clock).
  ASSERT_TRUE(simulation.pause()) << c.error();
  EXPECT_TRUE(simulation.paused());
  EXPECT_EQ(simulation.sim_time_us(), 0u);
  ASSERT_TRUE(simulation.resume()) << c.error();
  EXPECT_EQ(sim.wait_exit(kWaitMs), 0) << sim.err();
}

}  // namespace
}  // namespace troupe::testing
