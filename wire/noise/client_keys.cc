#include "wire/noise/client_keys.h"

#include "wire/noise/key_file.h"
#include "wire/noise/noise_transport.h"

namespace troupe::wire::noise {

bool client_options(const ClientKeys& keys, const std::string& host, uint16_t port, SecureOptions& out,
                    std::string& error) {
  if (keys.identity.empty()) {
    error = "a secure session needs --identity FILE (our secret key) with --node-key";
    return false;
  }
  out = SecureOptions{};
  out.role = Role::Initiator;
  // The known-nodes file writes an IPv6 host in brackets, as an address is typed.
  const bool v6 = host.find(':') != std::string::npos && host.front() != '[';
  const std::string host_port = (v6 ? "[" + host + "]" : host) + ":" + std::to_string(port);
  const bool node_key = keys.node_key.empty()
                            ? find_known_node(known_nodes_path(), host_port, out.peer_key, error)
                            : read_public_key(keys.node_key, out.peer_key, error);
  return node_key && read_secret_key(keys.identity, out.identity, error);
}

std::shared_ptr<NoiseTransport> client_transport(const ClientKeys& keys, const std::string& host,
                                                 uint16_t port, std::string& error) {
  error.clear();
  if (!keys.secure()) return nullptr;
  SecureOptions o;
  if (!client_options(keys, host, port, o, error)) return nullptr;
  return std::make_shared<NoiseTransport>(std::move(o));
}

}  // namespace troupe::wire::noise
