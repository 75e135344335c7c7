// A fixture serving a world with troupe-sim's runner, paused, on a free
// loopback port in its own thread: for tests that drive the simulator over
// the wire with the C++ client.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <thread>

#include "host-sim/troupe_sim/runner.h"
#include "tests/sim/temp_dir.h"

namespace troupe::sim::test {

class ServedWorld : public ::testing::Test {
 protected:
  /// The world file's text.
  explicit ServedWorld(const char* world) : world_(world) {}

  void SetUp() override {
    SimOptions o;
    o.world = dir_.write("w.world", world_);
    o.port = 0;
    o.paused = true;
    world::Diagnostics d;
    std::string error;
    ASSERT_TRUE(runner_.init(o, d, error)) << d.str() << error;
    thread_ = std::thread([this] { runner_.run(); });
  }
  void TearDown() override {
    runner_.request_stop();
    if (thread_.joinable()) thread_.join();
  }

  const char* world_;
  troupe::test::TempDir dir_;
  Runner runner_;
  std::thread thread_;
};

}  // namespace troupe::sim::test
