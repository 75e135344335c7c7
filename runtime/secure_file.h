// The --secure FILE of troupe-sim and troupe play: a file of the node config
// schema holding only "key" and "clients", read by node_secure.h as a node
// reads its config. Host programs only: it parses JSON.
#pragma once

#include <string>

#include "runtime/node_secure.h"

namespace troupe {

/// Reads `path`: JSON (or its flatc binary) of the node config schema
/// holding "key" and "clients" and nothing else, since those programs take
/// their address, port and devices from their own command line. False with
/// `error` naming the file when it cannot be read, has no key, or sets
/// anything else.
bool load_secure_sessions(const std::string& path, SecureSessions& out, std::string& error);

/// The help text of --secure, the same in every program that takes it.
extern const char kSecureFlagHelp[];

}  // namespace troupe
