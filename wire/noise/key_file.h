// Key files of secure sessions, as `troupe keygen NAME` writes them:
//
//   NAME      "troupe-x25519-secret <64 hex digits>\n", readable by its
//             owner only (mode 0600): the identity of a node or a client
//   NAME.pub  "troupe-x25519 <64 hex digits> NAME\n": what the other side
//             is given (a node's config lists its clients' .pub files; a
//             client names the node's public key)
//
// and a client's known nodes (as SSH's known_hosts): one node a line,
// "HOST:PORT <64 hex digits>" (an IPv6 host in brackets); blank lines and
// lines starting with '#' are skipped.
#pragma once

#include <string>

#include "wire/noise/handshake.h"

namespace troupe::wire::noise {

/// 64 lowercase hex digits.
std::string key_hex(const Key& key);
/// A key from 64 hex digits; false when `text` is not that.
bool parse_key_hex(std::string_view text, Key& out);

/// Writes a fresh key pair as `path` and `path`.pub (comment `name`).
/// Refuses to overwrite either; false with `error`.
bool write_key_pair(const std::string& path, const std::string& name, std::string& error);
/// Reads a secret key file. Refused when group or others may read it (as
/// SSH refuses), or when it is not a key file; false with `error`.
bool read_secret_key(const std::string& path, KeyPair& out, std::string& error);
/// Reads a public key: a .pub file, or 64 hex digits given directly.
bool read_public_key(const std::string& path_or_hex, Key& out, std::string& error);

/// The user's known-nodes file: $XDG_CONFIG_HOME/troupe/known_nodes, else
/// $HOME/.config/troupe/known_nodes ("" when neither variable is set).
std::string known_nodes_path();
/// The key `path` lists for `host_port` ("HOST:PORT"). False when the file
/// or the node is missing (`error` says which and how to add it), or the
/// node's line is malformed.
bool find_known_node(const std::string& path, const std::string& host_port, Key& out, std::string& error);

}  // namespace troupe::wire::noise
