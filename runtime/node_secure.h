// Secure sessions of troupe-node: the config's "key" and "clients" turned
// into the transport each connection runs through (wire/noise). Built into
// troupe-node only where libsodium is (the host; a board's sysroot when it
// carries it).
#pragma once

#include <string>

#include "runtime/node.h"
#include "runtime/node_config.h"

namespace troupe {

/// Reads the node's secret key and its clients' public keys (paths relative
/// to the config's folder) and sets `options.make_transport`. True without
/// change when the config names no key; false with `error` (naming the file
/// and the key) when a key cannot be read or no client is listed.
bool secure_sessions(const LoadedConfig& cfg, Node::Options& options, std::string& error);

}  // namespace troupe
