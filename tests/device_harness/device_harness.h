// Runs drivers the way troupe-node does, inside a test process: a Node
// built from a JSON config (the real config parser and driver table), on a
// free loopback port, stepped together with device emulators and wire
// clients by one loop in this thread. A driver that blocked would stall
// the emulators too, and the test would fail by its deadline.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "runtime/node.h"
#include "runtime/node_config.h"
#include "tests/device_harness/wire_client.h"

namespace troupe::testing {

/// A fresh folder for this test's links and files, removed with its
/// contents at the end.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

class NodeUnderTest {
 public:
  /// Builds and starts the node described by `json` (a node config; its
  /// port and listen address are replaced by a free loopback port). False
  /// with `error` as troupe-node would report it.
  bool start(const std::string& json, std::string& error);
  Node& node() { return *node_; }
  uint16_t port() const { return node_->port(); }

 private:
  LoadedConfig config_;
  std::unique_ptr<Node> node_;
};

/// Steps everything a test runs, in one thread.
class Loop {
 public:
  /// Called with the monotonic time, us, every iteration.
  using Step = std::function<void(uint64_t now_us)>;

  void add(NodeUnderTest& node) { nodes_.push_back(&node); }
  void add(WireClient& client) { clients_.push_back(&client); }
  void add(Step step) { steps_.push_back(std::move(step)); }

  /// Iterates until `done()` holds (true) or `timeout_s` passes (false).
  /// The timeout only bounds a failing test; nothing is timed.
  bool run_until(const std::function<bool()>& done, double timeout_s);
  /// Iterates for `seconds`.
  void run_for(double seconds);

 private:
  void iterate();

  std::vector<NodeUnderTest*> nodes_;
  std::vector<WireClient*> clients_;
  std::vector<Step> steps_;
};

/// The newest position2d state from `addr`, or nullptr.
const wire::Position2dState* position_state(const WireClient& client, const wire::Address& addr);

}  // namespace troupe::testing
