// Helpers around the generated Message type: header time, names of kinds and
// interfaces, and which interface a body belongs to.
#pragma once

#include <cstdint>
#include <string_view>

#include "wire/schemas/message_generated.h"

namespace troupe::wire {

/// The protocol version this build speaks (Hello.protocol_version).
inline constexpr uint16_t kProtocolVersion = 1;

/// Default TCP (and UDP) port of a node or simulator.
inline constexpr uint16_t kDefaultPort = 6665;

/// The sender's clock in a header, microseconds.
inline uint64_t time_us(const Header& h) {
  return (uint64_t{h.time_us_hi()} << 32) | h.time_us_lo();
}

/// A header for `addr` with the given kind, subtype, seq and time (us).
inline Header make_header(const Address& addr, Kind kind, uint8_t subtype, uint32_t seq,
                          uint64_t time_us) {
  return Header(addr, kind, subtype, seq, static_cast<uint32_t>(time_us),
                static_cast<uint32_t>(time_us >> 32));
}

inline bool operator==(const Address& a, const Address& b) {
  return a.robot() == b.robot() && a.iface() == b.iface() && a.index() == b.index();
}

/// Packs an address into one integer, for hashing and sorting.
inline uint64_t address_key(const Address& a) {
  return (uint64_t{a.robot()} << 32) | (uint64_t{a.iface()} << 16) | a.index();
}

/// "position2d", "ranger", ...; "interface-<n>" style names are not produced:
/// an unknown code gives "unknown".
std::string_view interface_name(uint16_t iface);
/// The code for an interface name, or Interface::None when unknown.
Interface interface_from_name(std::string_view name);

std::string_view kind_name(Kind kind);

/// The interface a body type belongs to. Session bodies give None; bodies
/// any interface may use (Switch) give `kAnyInterface`.
inline constexpr uint16_t kAnyInterface = 0xFFFF;
uint16_t body_interface(Body body);

/// True when a body of this type may travel in a message of this kind to or
/// from a device of this interface. Unknown (newer) body types return false;
/// check `is_known_body` first to tell "newer than us" from "wrong".
bool body_fits(Kind kind, uint16_t iface, Body body);

inline bool is_known_body(Body body) {
  return static_cast<uint8_t>(body) <= static_cast<uint8_t>(Body::MAX);
}

}  // namespace troupe::wire
