#include <cstdio>

#include "wire/address.h"
#include "wire/cli/cli.h"
#include "wire/noise/client_keys.h"
#include "wire/noise/noise_transport.h"

namespace troupe::cli {
namespace {

// --identity and --node-key, as the command line gave them (one command
// runs per process).
wire::noise::ClientKeys& secure_keys() {
  static wire::noise::ClientKeys keys;
  return keys;
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
  add_secure_session(app, secure_keys());
}

bool secure_options(const wire::HostPort& node, client::Client::Options& options) {
  std::string error;
  options.transport = wire::noise::client_transport(secure_keys(), node.host, node.port, error);
  if (!error.empty()) fail(error);
  return error.empty();
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
