// Node::command: a driver commanding a device of another driver. Kept in its
// own file: it is the client path of node.cc (handle_command) minus the
// client, and shares its delivery (deliver_commands).
#include "runtime/node.h"

namespace troupe {

void Node::command(DeviceId device, uint8_t subtype, wire::Body type, flatbuffers::Offset<void> body) {
  Device& dev = devices_[device];
  auto frame =
      writer_.finish(wire::make_header(dev.addr, wire::Kind::Command, subtype, 0, now_us()), type, body);
  // Newest wins: overwrite whatever command is still waiting.
  dev.command.assign(frame.begin(), frame.end());
  if (!dev.command_pending) {
    dev.command_pending = true;
    pending_commands_.push_back(device);
  }
}

}  // namespace troupe
