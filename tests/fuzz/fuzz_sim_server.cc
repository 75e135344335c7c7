// libFuzzer target: byte streams through troupe-sim's server (SimServer, the
// Driver behind every simulated device) in a real Node on loopback, serving
// a small world of two robots with a laser, the simulation:0 and map:0
// devices; the world steps between polls as troupe-sim's loop does
// (stream_harness.h).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "host-sim/troupe_sim/sim_server.h"
#include "tests/fuzz/stream_harness.h"

namespace {

constexpr const char* kWorld = R"(
resolution 0.02
interval_sim 100
model ( name "box" size [1 1] pose [3 0 0 0] )
define bot position ( size [0.4 0.4] localization "gps" localization_origin [0 0 0 0] )
bot ( name "r0" pose [0 0 0 0] ranger ( sensor ( range [0 5] fov 180 samples 19 ) ) )
bot ( name "r1" pose [-2 1 0 90] )
)";

// A Step request runs its steps before the answer; troupe-sim bounds them
// (wire::kMaxSteps). Here fewer keep each input fast; the code is the same.
constexpr uint32_t kMaxStepsPerRequest = 200;

struct Sim {
  std::unique_ptr<troupe::sim::World> world;
  troupe::sim::SimControl control;
  troupe::sim::SimServer* server = nullptr;
  troupe::Node node{troupe::fuzz::fuzz_node_options()};

  void step(uint32_t n) {
    for (uint32_t i = 0; i < n; ++i) {
      server->sync_wanted();
      world->step();
      server->publish();
    }
  }
};

uint64_t sim_clock_us(void* ctx) { return uint64_t(static_cast<troupe::sim::World*>(ctx)->time() * 1e6); }

troupe::fuzz::StreamHarness& harness() {
  static troupe::fuzz::StreamHarness* h = [] {
    char dir[] = "/tmp/fuzz-sim-XXXXXX";
    if (mkdtemp(dir) == nullptr) abort();
    const std::string path = std::string(dir) + "/small.world";
    std::ofstream(path) << kWorld;
    auto* sim = new Sim;
    troupe::world::Diagnostics diags;
    sim->world = troupe::sim::World::load(path, 1, diags);
    std::filesystem::remove_all(dir);
    if (!sim->world) {
      fprintf(stderr, "fuzz_sim_server: %s\n", diags.str().c_str());
      abort();
    }
    sim->control.step = [sim](uint32_t n) { sim->step(std::min(n, kMaxStepsPerRequest)); };
    sim->control.reset = [sim] {
      sim->world->reset();
      sim->world->refresh_sensors();
      sim->server->publish();
    };
    sim->node.set_clock(sim_clock_us, sim->world.get());
    auto server = std::make_unique<troupe::sim::SimServer>(*sim->world, sim->control);
    sim->server = server.get();
    std::string error;
    if (!sim->node.add_driver(std::move(server), troupe::DriverSetup{}, error) || !sim->node.start(error)) {
      fprintf(stderr, "fuzz_sim_server: %s\n", error.c_str());
      abort();
    }
    sim->server->sync_wanted();
    sim->world->refresh_sensors();
    // One step per poll while running, as troupe-sim steps between polls.
    return new troupe::fuzz::StreamHarness(sim->node, [sim] {
      if (!sim->control.paused) sim->step(1);
    });
  }();
  return *h;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  harness().run(data, size);
  return 0;
}
