// The v4l2 driver in a real node beside a kinematic base (the other device
// that must keep being served), a wire client over loopback TCP, all
// stepped in this thread (tests/device_harness).
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "tests/device_harness/device_harness.h"
#include "wire/schemas/message_generated.h"

namespace troupe::testing {

inline const wire::Address kCamera{0, uint16_t(wire::Interface::Camera), 0};
inline const wire::Address kOther{0, uint16_t(wire::Interface::Position2d), 0};

/// A node config with the camera's `options` (members of its driver
/// object, JSON) and the kinematic base.
inline std::string camera_config(const std::string& options) {
  return R"({ "drivers": [
    { "driver_type": "v4l2", "name": "cam", "driver": { )" +
         options + R"( }, "provides": ["camera:0"] },
    { "driver_type": "kinematic", "name": "other", "driver": { "rate_hz": 20 },
      "provides": ["position2d:0"] } ] })";
}

class CameraBench : public ::testing::Test {
 protected:
  /// Starts the node with the camera's `options`; false with error().
  bool start(const std::string& options) {
    if (!node_.start(camera_config(options), error_)) return false;
    if (!client_.connect(node_.port(), error_)) return false;
    loop_.add(node_);
    loop_.add(client_);
    client_.open(kCamera);
    client_.open(kOther);
    return true;
  }

  /// Sends a camera request and waits for its reply; nullptr when none
  /// came (a hang: the node answers Timeout by itself, so that is a bug).
  const wire::Message* ask(wire::CameraReqSub sub, wire::Body type = wire::Body::NONE,
                           flatbuffers::Offset<void> body = 0) {
    const uint32_t seq = client_.request(kCamera, uint8_t(sub), type, body);
    if (!loop_.run_until([&] { return client_.reply(seq) != nullptr; }, 30)) return nullptr;
    return client_.reply(seq);
  }

  /// The Nack's text, or "" for an Ack.
  static std::string nack_text(const wire::Message* m) {
    if (m == nullptr || m->header()->kind() != wire::Kind::Nack) return "";
    const auto* e = m->body_as_Error();
    return e && e->text() ? e->text()->str() : "(no text)";
  }

  const wire::CameraImage* image() const {
    const wire::Message* m = client_.last(kCamera);
    return m ? m->body_as_CameraImage() : nullptr;
  }

  const std::string& error() const { return error_; }

  NodeUnderTest node_;
  WireClient client_;
  Loop loop_;
  std::string error_;
};

}  // namespace troupe::testing
