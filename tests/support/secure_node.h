// A secure troupe-node for the tests of secure clients, set up as a user
// sets one up: `troupe keygen` for the node and its clients in a scratch
// folder, a config naming the node's key and the clients it accepts, and
// the real troupe-node serving it on a free loopback port.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tests/support/child_process.h"

namespace troupe::testing {

/// The drivers of a robot whose base is position2d:0, publishing at 20 Hz:
/// what most tests of secure clients read and drive.
inline constexpr char kKinematicBase[] =
    R"([ { "driver_type": "kinematic", "driver": { "rate_hz": 20 }, "provides": ["position2d:0"] } ])";

class SecureNodeProcess {
 public:
  /// Makes the folder and the key pairs "node" and each of `keys`
  /// (`folder`/NAME and NAME.pub). False with `error`.
  bool make_keys(const std::vector<std::string>& keys, std::string& error);
  /// Writes `folder`/node.json (the node's key, `clients` and `drivers`
  /// as JSON arrays) and starts troupe-node; true once it listens.
  bool start(const std::string& clients, const std::string& drivers, std::string& error);
  /// Stops the node and removes the folder.
  ~SecureNodeProcess();

  const std::string& dir() const { return dir_; }
  /// `folder`/`name`: a key file, a log, anything a test keeps there.
  std::string path(const std::string& name) const { return dir_ + "/" + name; }
  uint16_t port() const { return port_; }
  /// "127.0.0.1:PORT".
  std::string host() const { return "127.0.0.1:" + std::to_string(port_); }
  /// The node's public key as 64 hex digits (from node.pub).
  std::string node_key_hex() const;
  ChildProcess& node() { return node_; }

 private:
  std::string dir_;
  uint16_t port_ = 0;
  ChildProcess node_;
};

/// The arguments of a secure session as `identity` holding `node_key`:
/// {"--identity", folder/identity, "--node-key", folder/node_key}.
std::vector<std::string> secure_args(const SecureNodeProcess& node, const std::string& identity,
                                     const std::string& node_key);

}  // namespace troupe::testing
