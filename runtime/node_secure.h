// Secure sessions of the programs that serve devices: a node config's "key"
// and "clients" turned into the transport each connection runs through
// (wire/noise) and the rights of each client's key. troupe-node reads them
// from its config; troupe-sim and troupe play from a file of the same schema
// holding only those two (secure_file.h), so every server takes keys and
// rights the same way and refuses the same mistakes with the same words.
// Built where libsodium is (the host; a board's sysroot when it carries it).
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "runtime/node.h"

namespace troupe {

struct LoadedConfig;
namespace config {
struct NodeConfig;
}

/// What a secure server runs, to copy into each Node::Options it makes.
/// Empty (no transport): plain TCP.
struct SecureSessions {
  std::function<std::unique_ptr<wire::Transport>()> make_transport;
  std::function<std::shared_ptr<const Rights>(const std::string& peer)> rights_of;
  /// This server's public key, 64 hex digits: what its clients name with
  /// --node-key (its own viewer's bridge among them).
  std::string key_hex;

  bool on() const { return bool(make_transport); }
  void apply(Node::Options& options) const {
    options.make_transport = make_transport;
    options.rights_of = rights_of;
  }
};

/// Reads the node's secret key and its clients' public keys and rights from
/// `root` (key files relative to `config_path`'s folder). True and `out`
/// left empty when `root` names no key; false with `error` (naming the file,
/// the entry and the key) when a key cannot be read, a pattern is bad or no
/// client is listed.
bool secure_sessions(const config::NodeConfig& root, const std::string& config_path, SecureSessions& out,
                     std::string& error);

/// secure_sessions() of troupe-node's config, set into `options`.
bool secure_sessions(const LoadedConfig& cfg, Node::Options& options, std::string& error);

}  // namespace troupe
