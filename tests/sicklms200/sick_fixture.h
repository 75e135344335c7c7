// A node running the sicklms200 driver against the LMS200 emulator on a
// pty, beside a kinematic driver, with a client on loopback TCP opening
// both. Everything steps in this thread (tests/device_harness).
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "host-sim/emulators/sicklms200/sick_emulator.h"
#include "tests/device_harness/device_harness.h"
#include "tests/device_harness/raw_port.h"

namespace troupe::testing {

inline const wire::Address kLaser(0, uint16_t(wire::Interface::Ranger), 0);
inline const wire::Address kKinematic(0, uint16_t(wire::Interface::Position2d), 0);  // the kinematic driver

// The rig without GoogleTest's fixture, so a test parameterised over the
// serial drivers can hold one (tests/serial_port/serial_driver_alloc_test).
struct SickRig {
  std::string config(const std::string& options) const {
    std::string driver = "\"port\": \"" + dir_.file("laser") + "\"";
    if (!options.empty()) driver += ", " + options;
    return R"({ "name": "sick-test", "drivers": [
      { "driver_type": "sicklms200", "driver": { )" +
           driver + R"( }, "provides": ["ranger:0"] },
      { "driver_type": "kinematic", "driver": { "rate_hz": 20 }, "provides": ["position2d:0"] } ] })";
  }

  void start(emulators::SickEmulator::Config scanner_config = {}, const std::string& options = "",
             emulators::SickWorld* world = nullptr) {
    scanner_ = std::make_unique<emulators::SickEmulator>(scanner_config, world);
    std::string error;
    ASSERT_TRUE(scanner_->open(dir_.file("laser"), error)) << error;
    loop_.add([this](uint64_t now) { scanner_->step(now); });
    std::string node_error;
    ASSERT_TRUE(node_.start(config(options), node_error)) << node_error;
    ASSERT_TRUE(client_.connect(node_.port(), node_error)) << node_error;
    client_.open(kLaser);
    client_.open(kKinematic);
    loop_.add(node_);
    loop_.add(client_);
    // Every scan the client gets must be one the scanner sent: the world
    // stands still, so that is the scanner's last scan.
    loop_.add([this](uint64_t) { check_newest_scan(); });
  }

  const wire::RangerScan* newest_scan() const {
    const wire::Message* m = client_.last(kLaser);
    return m ? m->body_as_RangerScan() : nullptr;
  }
  bool streaming() {
    return loop_.run_until([&] { return client_.count(kLaser) >= 3; }, 20);
  }

  void check_newest_scan() {
    uint32_t n = client_.count(kLaser);
    if (n == checked_) return;
    checked_ = n;
    const wire::RangerScan* scan = newest_scan();
    std::span<const uint16_t> sent = scanner_->last_scan();
    bool same = scan && scan->ranges() && scan->ranges()->size() == sent.size();
    for (size_t i = 0; same && i < sent.size(); ++i) same = scan->ranges()->Get(uint32_t(i)) == sent[i];
    if (!same) ++mismatched_;
  }

  TempDir dir_;
  std::unique_ptr<emulators::SickEmulator> scanner_;
  NodeUnderTest node_;
  WireClient client_;
  Loop loop_;
  uint32_t checked_ = 0;
  uint32_t mismatched_ = 0;  // published scans unlike the scanner's
};

class SickNode : public ::testing::Test, public SickRig {};

}  // namespace troupe::testing
