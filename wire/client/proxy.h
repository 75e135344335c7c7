// Proxies: one object per remote device, holding its latest data and
// offering its commands and requests as methods (Player's client proxies).
// A proxy opens its device when constructed; the client re-opens it after a
// reconnect, so a proxy stays usable for the client's whole life.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "wire/client/client.h"

namespace troupe::client {

class Proxy {
 public:
  virtual ~Proxy();
  Proxy(const Proxy&) = delete;
  Proxy& operator=(const Proxy&) = delete;

  const wire::Address& address() const { return addr_; }
  /// Whether the Open was acknowledged (false: see client().error()).
  bool is_open() const { return open_; }
  /// Sender timestamp of the latest data, us (node clock); 0 before any.
  uint64_t time_us() const { return time_us_; }
  /// The device's sample counter at the latest data.
  uint32_t seq() const { return seq_; }
  /// Samples received so far.
  uint64_t samples() const { return samples_; }
  /// True once per new sample: reading it clears it.
  bool fresh() {
    bool f = fresh_;
    fresh_ = false;
    return f;
  }
  Client& client() { return *client_; }

 protected:
  Proxy(Client& client, const wire::Address& addr);
  /// Registers with the client and opens the device. Concrete proxies (all
  /// final) call it last in their constructor: data may arrive during the
  /// Open and must find the proxy fully built.
  void attach(wire::Access access = wire::Access::All, wire::Delivery delivery = wire::Delivery::Push,
              wire::ImageCompression compression = wire::ImageCompression::None);
  /// Decodes a Data message for this device (already verified).
  virtual void update(const wire::Message& msg) = 0;
  /// Sends a request for this device with the body begun in client().begin().
  Reply request(uint8_t subtype, wire::Body type = wire::Body::NONE, flatbuffers::Offset<void> body = 0,
                int timeout_ms = 2000);
  bool command(uint8_t subtype, wire::Body type, flatbuffers::Offset<void> body);

 private:
  friend class Client;
  void receive(const wire::Message& msg);

  Client* client_;
  wire::Address addr_;
  bool open_ = false;
  bool fresh_ = false;
  uint64_t time_us_ = 0;
  uint32_t seq_ = 0;
  uint64_t samples_ = 0;
};

/// Copies a FlatBuffers vector of structs (which yields pointers) into `out`.
template <typename T>
void copy_structs(const flatbuffers::Vector<const T*>* in, std::vector<T>& out) {
  out.clear();
  if (in == nullptr) return;
  out.reserve(in->size());
  for (const T* item : *in) out.push_back(*item);
}

/// An address on robot `robot` of interface `iface`, instance `index`.
inline wire::Address address_of(wire::Interface iface, uint16_t index = 0, uint16_t robot = 0) {
  return wire::Address(robot, uint16_t(iface), index);
}

}  // namespace troupe::client
