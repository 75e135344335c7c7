#include <cstdio>

#include "wire/address.h"
#include "wire/cli/cli.h"
#include "wire/noise/key_file.h"
#include "wire/noise/noise_transport.h"

namespace troupe::cli {
namespace {

// --identity and --node-key, as the command line gave them (one command
// runs per process).
struct SecureFlags {
  std::string identity, node_key;
};
SecureFlags& secure_flags() {
  static SecureFlags flags;
  return flags;
}

}  // namespace

int fail(const std::string& message) {
  fprintf(stderr, "troupe: %s\n", message.c_str());
  return kExitFailure;
}

int usage_error(std::string_view command, const std::string& message) {
  fprintf(stderr, "troupe %.*s: %s (see: troupe %.*s --help)\n", int(command.size()), command.data(), message.c_str(),
          int(command.size()), command.data());
  return kExitUsage;
}

void add_host(CLI::App& app, std::string& host) {
  app.add_option("HOST", host, "HOST[:PORT]")->required();
  app.add_option("--identity", secure_flags().identity,
                 "a secure session: our secret key file (troupe keygen NAME writes one)")
      ->type_name("FILE");
  app.add_option("--node-key", secure_flags().node_key,
                 "a secure session: the node's public key (its NAME.pub, or 64 hex digits); default: "
                 "the node's line in the known-nodes file (~/.config/troupe/known_nodes)")
      ->type_name("KEY");
}

bool secure_options(const wire::HostPort& node, client::Client::Options& options) {
  const SecureFlags& f = secure_flags();
  if (f.identity.empty() && f.node_key.empty()) return true;
  if (f.identity.empty()) {
    fail("a secure session needs --identity FILE (our secret key) with --node-key");
    return false;
  }
  wire::noise::SecureOptions o;
  std::string error;
  const bool v6 = node.host.find(':') != std::string::npos && node.host.front() != '[';
  const std::string host_port = (v6 ? "[" + node.host + "]" : node.host) + ":" + std::to_string(node.port);
  const bool node_key = f.node_key.empty()
                            ? wire::noise::find_known_node(wire::noise::known_nodes_path(), host_port, o.peer_key, error)
                            : wire::noise::read_public_key(f.node_key, o.peer_key, error);
  if (!node_key || !wire::noise::read_secret_key(f.identity, o.identity, error)) {
    fail(error);
    return false;
  }
  options.transport = std::make_shared<wire::noise::NoiseTransport>(std::move(o));
  return true;
}

void add_device(CLI::App& app, std::string& addr) {
  app.add_option("ADDR", addr, "[ROBOT/]INTERFACE:INDEX")->required();
}

std::unique_ptr<client::Client> connect(const std::string& host_port, bool reconnect) {
  wire::HostPort hp;
  std::string error;
  if (!wire::parse_host(host_port, hp, error)) {
    fail(error);
    return nullptr;
  }
  client::Client::Options options;
  options.name = "troupe-cli";
  options.reconnect = reconnect;
  if (!secure_options(hp, options)) return nullptr;
  auto c = std::make_unique<client::Client>(hp.host, hp.port, options);
  if (!c->connect(3000)) {
    fail(c->error());
    return nullptr;
  }
  return c;
}

bool resolve(client::Client& c, const std::string& spec, wire::Address& out) {
  if (!c.resolve(spec, out)) {
    fprintf(stderr, "troupe: %s\n", c.error().c_str());
    return false;
  }
  return true;
}

}  // namespace troupe::cli
