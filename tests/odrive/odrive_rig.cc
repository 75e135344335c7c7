#include "tests/odrive/odrive_rig.h"

#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>

#include "drivers/odrive_can/can_io.h"
#include "runtime/node_config.h"

namespace troupe::testing {
namespace {

Node::Options node_options_for_tests() {
  Node::Options o;
  o.name = "odrive-rig";
  o.listen = "127.0.0.1";
  o.port = 0;  // any free port
  o.udp = false;
  return o;
}

}  // namespace

bool build_node_from_json(Node& node, const std::string& json, std::vector<uint8_t>& bytes,
                          std::string& error) {
  LoadedConfig cfg;
  cfg.path = "rig.json";
  if (!parse_config_json(json, cfg.path, cfg.bytes, error)) return false;
  flatbuffers::Verifier verifier(cfg.bytes.data(), cfg.bytes.size());
  if (!config::VerifyNodeConfigBuffer(verifier)) {
    error = "the config did not verify";
    return false;
  }
  cfg.root = config::GetNodeConfig(cfg.bytes.data());
  if (!build_node(node, cfg, error)) return false;
  bytes = std::move(cfg.bytes);  // drivers keep reading their options from it
  return true;
}

OdriveRig::OdriveRig(RigConfig config) : node(node_options_for_tests()) {
  if (config.axes.empty()) {
    for (uint8_t id : {kLeft, kRight}) {
      emulators::odrive::AxisConfig a;
      a.node_id = id;
      a.watchdog_timeout_ms = 500;
      config.axes.push_back(a);
    }
  }
  // The vcan VM test runs this same bench over a kernel interface.
  if (const char* iface = getenv("TROUPE_TEST_CAN_INTERFACE"); iface && config.can_interface.empty()) {
    config.can_interface = iface;
  }
  can_interface_ = config.can_interface;
  std::string bus;
  if (config.can_interface.empty()) {
    int pair[2];
    if (socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, pair) != 0) {
      error_ = "socketpair failed";
      return;
    }
    driver_fd_ = pair[0];
    emulator_fd_ = pair[1];
    bus = "\"descriptor\": " + std::to_string(driver_fd_);
  } else {
    emulator_fd_ = cansimple::open_can_socket(config.can_interface, {}, error_);
    if (emulator_fd_ < 0) return;
    bus = "\"can_interface\": \"" + config.can_interface + "\"";
  }
  emulators::odrive::EmulatorOptions eo;
  eo.axes = config.axes;
  eo.seed = config.seed;
  emu = std::make_unique<emulators::odrive::OdriveEmulator>(node.loop(), emulator_fd_, eo);
  if (!emu->start(error_)) return;

  std::string json = R"({ "drivers": [
    { "driver_type": "odrive_can", "name": "base",
      "driver": { )" +
                     bus + (config.driver_options.empty() ? "" : ", " + config.driver_options) +
                     R"( },
      "provides": ["position2d:0", "power:0"] },
    { "driver_type": "kinematic", "name": "other", "driver": { "rate_hz": 20 },
      "provides": ["position2d:1"] } ] })";
  if (!build_node_from_json(node, json, config_bytes_, error_)) return;
  if (!node.start(error_)) return;
  if (!client.connect(node.port(), error_)) return;
  for (const wire::Address& a : {kBase, kPower, kOther}) client.open(a);
}

OdriveRig::~OdriveRig() {
  node.shutdown();
  // The driver's last frames (stop, IDLE) reach the emulator before it goes.
  if (emu) {
    for (int i = 0; i < 5; ++i) node.loop().run_once(1000);
    emu->stop();
  }
  emu.reset();
  if (driver_fd_ >= 0) close(driver_fd_);
  if (emulator_fd_ >= 0) close(emulator_fd_);
}

bool OdriveRig::run_until(const std::function<bool()>& done, double max_s) {
  const uint64_t end = node.loop().now_us() + uint64_t(max_s * 1e6);
  while (!done()) {
    if (node.loop().now_us() >= end) return false;
    node.poll(5000);
    client.pump();
  }
  return true;
}

void OdriveRig::run_for(double seconds) {
  run_until([] { return false; }, seconds);
}

void OdriveRig::close_bus() {
  emu->stop();
  if (emulator_fd_ >= 0) close(emulator_fd_);
  emulator_fd_ = -1;
}

bool OdriveRig::restart_emulator(std::string& error) {
  emulators::odrive::EmulatorOptions eo = emu->options();
  emu->stop();
  if (emulator_fd_ >= 0) close(emulator_fd_);
  emulator_fd_ = cansimple::open_can_socket(can_interface_, {}, error);
  if (emulator_fd_ < 0) return false;
  emu = std::make_unique<emulators::odrive::OdriveEmulator>(node.loop(), emulator_fd_, eo);
  return emu->start(error);
}

}  // namespace troupe::testing
