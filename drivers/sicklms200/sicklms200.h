// sicklms200: a SICK LMS200/291 laser scanner on a serial port.
//
// Provides: ranger (exactly one): a scan per telegram, ranges in mm up to
// 8.191 m (no return), first beam at minus half the scan width.
// Requests: ranger Geometry (the pose option), GetConfig.
//
// An explicit state machine, driven by bytes from the port and a 20 Hz tick,
// never blocking the node's loop. Each configuration step sends one request
// and waits for its reply (resent on a timeout, reply_attempts times):
//
//   Closed -open-> Connect -A0-> SwitchBaud -A0-> Variant -BB-> ReadConfig
//     ^            (enter config;  (if not at     (width,       -F4-> WriteConfig
//     |             no reply: next  the target     resolution)        (units mm) -F7->
//     |             probe baud)     baud yet)                   Start -A0-> Streaming
//     +-- port lost, or no baud answers: reopen with backoff --+   no scan for a while:
//                                                                   back to Connect
#pragma once

#include <cstdint>
#include <string>

#include "drivers/serial_port/serial_session.h"
#include "drivers/sicklms200/sick_protocol.h"
#include "runtime/driver.h"

namespace troupe::drivers::sicklms200 {

class SickLms200 final : public Driver, private serial::SerialSession::Listener {
 public:
  enum class State : uint8_t {
    Closed,
    Connect,
    SwitchBaud,
    Variant,
    ReadConfig,
    WriteConfig,
    Start,
    Streaming
  };

  SickLms200();
  bool setup(Node& node, const DriverSetup& setup, std::string& error) override;
  void on_request(DeviceId device, const wire::Message& request, RequestToken token) override;
  void shutdown() override;

 private:
  // The configuration steps, each one request and its reply.
  void probe(size_t index);
  void ask(State state, const Telegram& request, uint8_t reply);
  void handle(std::span<const uint8_t> body);
  void on_reply(const Reply& reply);
  void on_timeout();
  void publish(const Scan& scan);
  // What the serial session reports.
  void on_session_open() override;
  void on_session_bytes(std::span<const uint8_t> bytes) override;
  void on_session_tick(uint64_t now_us) override;
  void on_session_down() override;

  serial::SerialSession session_;
  TelegramScanner scanner_{kReplyAddress};
  std::string name_ = "sicklms200";
  DeviceId ranger_ = kNoDevice;

  // Options.
  uint32_t target_baud_ = 38400;
  uint16_t width_deg_ = 180, resolution_cdeg_ = 100;
  float pose_x_ = 0, pose_y_ = 0, pose_yaw_ = 0;
  uint64_t reply_timeout_us_ = 0, scan_timeout_us_ = 0;
  uint32_t reply_attempts_ = 0;

  // State machine.
  State state_ = State::Closed;
  size_t probe_index_ = 0;
  Telegram pending_;    // the request waiting for its reply
  uint8_t expect_ = 0;  // the reply code it waits for
  uint32_t attempts_ = 0;
  uint64_t last_scan_us_ = 0;
  uint8_t config_[kConfigBytes] = {};
  size_t config_size_ = 0;
  uint16_t expected_count_ = 0;
  uint32_t scans_dropped_ = 0;
  Scan scan_;
};

}  // namespace troupe::drivers::sicklms200
