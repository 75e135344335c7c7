// passthrough: devices of a remote node (a robot board, troupe-sim, another
// passthrough) served by this node under local addresses, so the desktop's
// drivers (mcl, fusion) and clients use them as if they were local.
//
// Provides: the forwarded devices, provides[i] for remote[i]; optionally one
// `opaque` device last, which reports the link's state.
// Data from the remote is republished locally with the remote's timestamps;
// local commands go to the remote (the newest wins while the link is busy;
// while it is down they are dropped, not replayed later); requests are
// forwarded and answered with the remote's reply, or Nack DeviceFailed when
// the link drops first (the node answers Timeout itself past its deadline).
// When the remote goes away the link reconnects with backoff and opens the
// devices again; local clients keep their connections and see data resume.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "drivers/passthrough/remote_link.h"
#include "runtime/driver.h"
#include "runtime/node_config.h"
#include "wire/address.h"

namespace troupe::drivers::passthrough {

class Passthrough : public Driver, public LinkListener {
 public:
  bool setup(Node& node, const DriverSetup& setup, std::string& error) override;
  void on_command(DeviceId device, const wire::Message& command) override;
  void on_request(DeviceId device, const wire::Message& request, RequestToken token) override;
  void on_timer(TimerId id) override;
  void shutdown() override;

  void on_link_up() override;
  void on_link_down(const std::string& why) override;
  void on_remote_frame(const wire::Message& msg) override;
  void on_link_writable() override;

  const RemoteLink& link() const { return *link_; }
  /// The status text the opaque device publishes (JSON, one object).
  std::string status_text() const;

 private:
  struct Forwarded {
    DeviceId local = kNoDevice;
    wire::DeviceSpec spec;         // as the options name it
    wire::Address remote{};        // resolved from the remote's device list
    std::vector<uint8_t> command;  // newest command frame not yet sent
    bool command_pending = false;
  };
  struct InFlight {
    bool active = false;
    uint32_t remote_seq = 0;
    RequestToken token;
  };

  bool resolve_devices(const wire::Message& list);
  Forwarded* by_local(DeviceId device);
  Forwarded* by_remote(const wire::Address& addr);
  void forward_reply(const wire::Message& reply);
  void send_commands();
  void fail_requests(const std::string& why);
  void publish_status();

  std::string name_;
  std::unique_ptr<RemoteLink> link_;
  std::vector<Forwarded> devices_;
  std::vector<InFlight> in_flight_;
  DeviceId status_ = kNoDevice;
  TimerId status_timer_ = 0;
  uint32_t list_seq_ = 0;     // the DeviceList request of this connection
  bool opened_ = false;       // devices resolved and opened on this connection
  uint64_t since_us_ = 0;     // loop time opened_ last changed (or setup), us
  std::string logged_error_;  // the last failure logged, to log a repeat once
  wire::MessageWriter writer_;
};

}  // namespace troupe::drivers::passthrough
