// What the server fuzz targets share: each input is the byte stream of one
// TCP connection to a real Node on loopback, cut into writes as the input's
// first byte says, with the node's loop run between writes, so every frame
// the node accepts is dispatched to its handler (the drivers' included).
// After each input a well-behaved client, connected since the start, must
// still be served: its Pull of position2d:0 (robot 0) answered with finite
// odometry and its device list request with the list. Anything else traps,
// which libFuzzer reports as a crash with the input that caused it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>

#include "runtime/node.h"

namespace troupe::fuzz {

class StreamHarness {
 public:
  /// `node` has started (its port is bound). `tick` runs after each poll of
  /// the node's loop (a simulator steps its world there).
  StreamHarness(Node& node, std::function<void()> tick = {});

  /// Runs one libFuzzer input through a fresh connection, then checks the
  /// well-behaved client.
  void run(const uint8_t* data, size_t size);

 private:
  void pump(int64_t wait_us);
  void check_served();

  Node& node_;
  std::function<void()> tick_;
  int good_ = -1;  // the well-behaved client's socket
  uint32_t seq_ = 0;
};

/// Node options for a fuzz target: loopback, a kernel-chosen port, no UDP
/// (a fuzzed Hello must not send datagrams to arbitrary local ports).
Node::Options fuzz_node_options();

}  // namespace troupe::fuzz
