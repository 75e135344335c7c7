// A test bench: a real troupe::Node running the odrive_can driver (and a
// kinematic base beside it, the "other device" that must keep being served),
// the ODrive emulator on the same loop, and a TCP client of the node.
// Driver and emulator talk over a socketpair(AF_UNIX, SOCK_SEQPACKET), or
// both over a kernel CAN interface (vcan0 in the VM test).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "host-sim/emulators/odrive/odrive_emulator.h"
#include "runtime/node.h"
#include "tests/odrive/test_client.h"

namespace troupe::testing {

struct RigConfig {
  /// Empty: a socketpair. Otherwise the SocketCAN interface both open.
  std::string can_interface;
  /// More members of the driver's options object, JSON, e.g.
  /// "\"invert_right\": true, \"command_timeout_ms\": 300".
  std::string driver_options;
  /// Emulated axes; default: nodes 0 (left) and 1 (right), watchdog 500 ms.
  std::vector<emulators::odrive::AxisConfig> axes;
  uint64_t seed = 1;
};

/// A default bench whose driver gets these extra options.
inline RigConfig with_options(std::string driver_options) {
  RigConfig c;
  c.driver_options = std::move(driver_options);
  return c;
}

class OdriveRig {
 public:
  static constexpr uint8_t kLeft = 0, kRight = 1;  // default node ids
  static inline const wire::Address kBase{0, uint16_t(wire::Interface::Position2d), 0};
  static inline const wire::Address kPower{0, uint16_t(wire::Interface::Power), 0};
  static inline const wire::Address kOther{0, uint16_t(wire::Interface::Position2d), 1};

  explicit OdriveRig(RigConfig config = {});
  ~OdriveRig();

  /// Empty when the bench is up; else what failed.
  const std::string& error() const { return error_; }

  /// Runs the node's loop (driver, emulator, server) and the client until
  /// `done` holds or `max_s` seconds of loop time passed. Returns done().
  bool run_until(const std::function<bool()>& done, double max_s);
  void run_for(double seconds);

  /// The emulator's end of the bus goes away (socketpair only).
  void close_bus();
  /// A fresh emulator on a new socket of the same interface (kernel CAN
  /// only), for after the interface was deleted and created again.
  bool restart_emulator(std::string& error);
  /// The kernel interface in use, or "" on a socketpair.
  const std::string& can_interface() const { return can_interface_; }

  emulators::odrive::Axis& left() { return *emu->axis(kLeft); }
  emulators::odrive::Axis& right() { return *emu->axis(kRight); }
  PositionSample base() { return client.position(kBase); }
  PositionSample other() { return client.position(kOther); }

  Node node;
  std::unique_ptr<emulators::odrive::OdriveEmulator> emu;
  TestClient client;

 private:
  std::string error_;
  std::string can_interface_;
  int driver_fd_ = -1, emulator_fd_ = -1;
  std::vector<uint8_t> config_bytes_;
};

/// Builds `node` from JSON node-config text, as troupe-node would from a
/// file. False with `error`.
bool build_node_from_json(Node& node, const std::string& json, std::vector<uint8_t>& bytes,
                          std::string& error);

}  // namespace troupe::testing
