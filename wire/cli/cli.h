// Shared pieces of the troupe command-line tool.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "wire/address.h"
#include "wire/cli/args.h"
#include "wire/client/client.h"

namespace troupe::cli {

/// Prints "troupe: <message>" to stderr and returns kExitFailure.
int fail(const std::string& message);
/// Prints "troupe <cmd>: <message> (see: troupe <cmd> --help)", one line, and
/// returns kExitUsage.
int usage_error(std::string_view command, const std::string& message);

/// The positional arguments every built-in command starts with: the node
/// (HOST[:PORT]) and, but for ls, a device ([ROBOT/]INTERFACE:INDEX).
void add_host(CLI::App& app, std::string& host);
void add_device(CLI::App& app, std::string& addr);

/// Adds a secure session's transport to `options` when --identity was
/// given (add_host() adds it and --node-key; without --node-key the key is
/// `node`'s line in the known-nodes file); prints and returns false when a
/// key cannot be read or found.
bool secure_options(const wire::HostPort& node, client::Client::Options& options);
/// Parses "HOST[:PORT]" and connects; on failure prints one line and returns
/// nullptr. `reconnect`: keep trying after a lost connection (echo, teleop).
std::unique_ptr<client::Client> connect(const std::string& host_port, bool reconnect = false);
/// Resolves "[ROBOT/]INTERFACE:INDEX" on the connected node; prints on failure.
bool resolve(client::Client& c, const std::string& spec, wire::Address& out);

/// One line describing a message: "t=12.345678 seq=7 pose=... vel=...".
std::string summary(const wire::Message& msg);
/// The message as one line of JSON (field names quoted).
std::string to_json(const wire::Message& msg);
/// Only the body, as JSON ("{}" when there is none).
std::string body_json(const wire::Message& msg);

/// The built-in commands: each parses its arguments (--help prints its
/// help, so `troupe help NAME` runs it with {"--help"}) and runs.
int cmd_ls(const std::vector<std::string>& args);
int cmd_echo(const std::vector<std::string>& args);
int cmd_send(const std::vector<std::string>& args, wire::Kind kind);  // cmd and req
int cmd_teleop(const std::vector<std::string>& args);
int cmd_keygen(const std::vector<std::string>& args);

/// The verbs of `cmd`/`req` for an interface, a line each with arguments
/// and units (for help), or comma-separated names only (for errors).
std::string verb_list(wire::Interface iface, wire::Kind kind, bool names_only = false);

}  // namespace troupe::cli
