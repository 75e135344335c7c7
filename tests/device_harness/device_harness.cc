#include "tests/device_harness/device_harness.h"

#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <filesystem>

#include "runtime/clock.h"

namespace troupe::testing {

TempDir::TempDir() {
  std::string pattern = ::testing::TempDir() + "troupe-XXXXXX";
  char* made = mkdtemp(pattern.data());
  path_ = made ? made : "";
}

TempDir::~TempDir() {
  std::error_code ignored;
  if (!path_.empty()) std::filesystem::remove_all(path_, ignored);
}

bool NodeUnderTest::start(const std::string& json, std::string& error) {
  config_ = LoadedConfig{};
  config_.path = "test-node.json";
  if (!parse_config_json(json, config_.path, config_.bytes, error)) return false;
  config_.root = config::GetNodeConfig(config_.bytes.data());
  Node::Options options = node_options(*config_.root);
  options.listen = "127.0.0.1";
  options.port = 0;
  options.udp = false;
  node_ = std::make_unique<Node>(options);
  return build_node(*node_, config_, error) && node_->start(error);
}

void Loop::iterate() {
  // The node waits at most 2 ms, so emulators run at least 500 times a
  // second: far finer than any serial timing they model.
  for (NodeUnderTest* n : nodes_) n->node().poll(2000);
  uint64_t now = monotonic_us();
  for (const Step& s : steps_) s(now);
  for (WireClient* c : clients_) c->poll();
}

bool Loop::run_until(const std::function<bool()>& done, double timeout_s) {
  uint64_t end = monotonic_us() + uint64_t(timeout_s * 1e6);
  while (!done()) {
    if (monotonic_us() > end) return false;
    iterate();
  }
  return true;
}

void Loop::run_for(double seconds) {
  uint64_t end = monotonic_us() + uint64_t(seconds * 1e6);
  while (monotonic_us() < end) iterate();
}

const wire::Position2dState* position_state(const WireClient& client, const wire::Address& addr) {
  const wire::Message* m = client.last(addr);
  return m ? m->body_as_Position2dState() : nullptr;
}

}  // namespace troupe::testing
