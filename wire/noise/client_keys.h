// A client's side of a secure session, from what its user names: our
// identity (a secret key file) and the node's public key, or else the node's
// line in the known-nodes file (key_file.h). Every C++ peer that opens
// sessions (the troupe CLI, troupe record, troupe view, troupe ros2, the
// passthrough driver) reads its keys here, so they take the same keys the
// same way and fail with the same messages.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

namespace troupe::wire::noise {

struct SecureOptions;
class NoiseTransport;

/// What the user named; both empty: plain TCP.
struct ClientKeys {
  /// Our secret key file (`troupe keygen NAME` writes one).
  std::string identity;
  /// The node's public key: its NAME.pub file, or 64 hex digits. Empty: the
  /// node's line in the known-nodes file.
  std::string node_key;

  bool secure() const { return !identity.empty() || !node_key.empty(); }
};

/// The initiator's options of a session with the node at `host`:`port`
/// (`host` as resolved names it: an IPv6 address with or without brackets).
/// False with `error` when a key cannot be read, the node is not in the
/// known-nodes file, or a node key is named without an identity. The texts
/// name the command-line options (--identity, --node-key).
bool client_options(const ClientKeys& keys, const std::string& host, uint16_t port, SecureOptions& out,
                    std::string& error);

/// client_options() as a transport for the connection core. nullptr with
/// `error` empty when `keys` ask for no secure session; nullptr with `error`
/// when they cannot be read.
std::shared_ptr<NoiseTransport> client_transport(const ClientKeys& keys, const std::string& host,
                                                 uint16_t port, std::string& error);

}  // namespace troupe::wire::noise
