// A wire protocol client for tests: loopback TCP over the connection core
// (wire/connection), never blocking, since the node runs in the same
// thread. poll() takes whatever frames have arrived and files them: the
// newest Data frame and a count per device, replies by sequence number.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "wire/connection/socket_link.h"
#include "wire/writer.h"

namespace troupe::testing {

class WireClient {
 public:
  WireClient() = default;
  WireClient(const WireClient&) = delete;
  WireClient& operator=(const WireClient&) = delete;

  bool connect(uint16_t port, std::string& error);
  /// Opens a device for reading and writing (data pushed).
  void open(const wire::Address& addr);
  /// Commands a velocity: m/s forward, rad/s.
  void send_vel(const wire::Address& addr, float v, float w);
  /// Starts a body for request(): build it in the returned builder.
  flatbuffers::FlatBufferBuilder& begin() { return writer_.start(); }
  /// Sends a request with the body built since begin() (or none). Returns
  /// the sequence number the reply will carry.
  uint32_t request(const wire::Address& addr, uint8_t subtype, wire::Body type = wire::Body::NONE,
                   flatbuffers::Offset<void> body = 0);
  uint32_t request_switch(const wire::Address& addr, uint8_t subtype, bool on);

  /// Reads and files every frame that has arrived.
  void poll();

  /// Data frames received from `addr` so far.
  uint32_t count(const wire::Address& addr) const;
  /// The newest Data message from `addr`, or nullptr.
  const wire::Message* last(const wire::Address& addr) const;
  /// The reply (Ack or Nack) to request `seq`, or nullptr.
  const wire::Message* reply(uint32_t seq) const;
  /// The connection ended or broke.
  bool closed() const { return closed_; }

 private:
  void send(std::span<const uint8_t> frame);
  uint32_t next_seq() { return link_->connection().next_seq(); }

  std::unique_ptr<wire::SocketLink> link_;
  bool closed_ = false;
  wire::MessageWriter writer_;
  struct Log {
    uint32_t count = 0;
    std::vector<uint8_t> last;
  };
  std::map<uint64_t, Log> data_;
  std::map<uint32_t, std::vector<uint8_t>> replies_;
};

}  // namespace troupe::testing
