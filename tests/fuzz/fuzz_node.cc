// libFuzzer target: byte streams through a real Node serving the kinematic
// base (position2d:0) on loopback, every accepted frame dispatched to its
// handler, and a well-behaved client checked after each input
// (stream_harness.h). The seeds are one valid frame of every message a
// client sends (tests/wire/samples.h).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>

#include "drivers/kinematic/kinematic.h"
#include "tests/fuzz/stream_harness.h"

namespace {

troupe::fuzz::StreamHarness& harness() {
  static troupe::fuzz::StreamHarness* h = [] {
    auto* node = new troupe::Node(troupe::fuzz::fuzz_node_options());
    auto* driver = new troupe::drivers::kinematic::Kinematic;
    static troupe::DeviceId base = node->add_device(
        troupe::wire::Address(0, uint16_t(troupe::wire::Interface::Position2d), 0), driver, "kinematic");
    troupe::DriverSetup setup;
    setup.name = "kinematic";
    setup.provides = {&base, 1};
    std::string error;
    if (!node->add_driver(std::unique_ptr<troupe::Driver>(driver), setup, error) || !node->start(error)) {
      fprintf(stderr, "fuzz_node: %s\n", error.c_str());
      abort();
    }
    return new troupe::fuzz::StreamHarness(*node);
  }();
  return *h;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  harness().run(data, size);
  return 0;
}
