// The driver contract. A driver is a class in its own folder under drivers/;
// the board lists which drivers are compiled in. See runtime/README.md.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "runtime/event_loop.h"
#include "wire/message.h"

namespace troupe {

namespace config {
struct DriverInstance;
}

class Node;

/// A device of this node: an index into the node's registry, valid for the
/// node's life.
using DeviceId = uint32_t;
inline constexpr DeviceId kNoDevice = 0xFFFFFFFFu;

/// A request waiting for its reply. Pass it to exactly one of Node::ack() or
/// Node::nack(), now or later; the node answers Timeout by itself when the
/// deadline passes first, and then ignores the late reply.
struct RequestToken {
  uint32_t slot = 0xFFFFFFFFu;
  uint32_t generation = 0;
};

/// What a driver instance is given at setup.
struct DriverSetup {
  /// The instance's entry in the node config; read options through
  /// OptionsView (runtime/node_config.h).
  const config::DriverInstance* instance = nullptr;
  /// The instance name used in log lines.
  std::string name;
  /// Devices this instance provides (registered already), in config order.
  std::span<const DeviceId> provides;
  /// Devices this instance requires (provided by other instances), in config
  /// order. The driver gets their data through on_data() once it subscribes.
  std::span<const DeviceId> required;
  /// The config file's path ("" when the config came from elsewhere): a
  /// file an option names is relative to its folder (config_relative()).
  std::string config_path;
};

/// Why a driver refused to set up, which decides what the node says last:
/// the config must change, or the machine lacks what the driver drives
/// (no such CAN interface, no CAN in the kernel) and the same config works
/// where it is there.
enum class SetupFailure : uint8_t { Config, MissingDevice };

class Driver : public FdHandler, public TimerHandler {
 public:
  virtual ~Driver() = default;

  /// Reads options, opens hardware, registers descriptors and timers. On
  /// failure returns false with `error` saying what and where (the node then
  /// refuses to start: never half-configured), and `setup_failure_` set to
  /// MissingDevice when the hardware is not there rather than misconfigured.
  virtual bool setup(Node& node, const DriverSetup& setup, std::string& error) = 0;

  /// The newest command for one of this driver's devices. Commands that
  /// arrived in the same loop iteration before it were replaced by it.
  virtual void on_command(DeviceId /*device*/, const wire::Message& /*command*/) {}

  /// A request for one of this driver's devices. Reply once through the
  /// node with `token`. The default refuses it as unsupported.
  virtual void on_request(DeviceId device, const wire::Message& request, RequestToken token);

  /// A client opened `device`, one of this driver's, for reading when nobody
  /// read it. The node then hands the new reader the device's stored
  /// samples: a driver that publishes only while a device is read
  /// publishes the current sample now (or drops what is stale with
  /// Node::forget_data), so that the first sample a reader sees is current.
  virtual void on_read_start(DeviceId /*device*/) {}

  /// A client opened `device` for reading asking for images packed as
  /// `compression` (its Open's), which no other reader of it asked for;
  /// called after on_read_start(), before the reader is added. A camera
  /// that packs images per reader (Node::publish_packed) publishes its
  /// current image so packed now, for the same reason as on_read_start().
  virtual void on_packing_start(DeviceId /*device*/, wire::ImageCompression /*compression*/) {}

  /// Data published by a device this driver subscribed to (Node::subscribe).
  virtual void on_data(DeviceId /*source*/, const wire::Message& /*data*/) {}

  /// The reply (Ack or Nack, with the request's subtype and seq) to a
  /// request this driver sent to `device` with Node::request(). The message
  /// is valid during the call only.
  virtual void on_reply(DeviceId /*device*/, const wire::Message& /*reply*/) {}

  void on_fd(int /*fd*/, uint32_t /*events*/) override {}
  void on_timer(TimerId /*id*/) override {}

  /// Stop motors, close hardware. Called once, in reverse setup order.
  virtual void shutdown() {}

 protected:
  Node* node_ = nullptr;
  SetupFailure setup_failure_ = SetupFailure::Config;
  friend class Node;
};

/// One entry of the board's driver table (generated from boards/<board>/).
struct DriverEntry {
  const char* name;     // as in the node config's "driver_type"
  Driver* (*create)();  // new instance, owned by the node
};

/// The drivers compiled into this board, ended by nullptr (generated from
/// boards/<board>/board.cmake).
extern const DriverEntry* const kBoardDrivers[];
/// The board's name.
extern const char* const kBoardName;

}  // namespace troupe
