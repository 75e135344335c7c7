#include "runtime/node_secure.h"

#include <algorithm>

#include "runtime/log.h"
#include "wire/noise/key_file.h"
#include "wire/noise/noise_transport.h"

namespace troupe {
namespace {

namespace noise = wire::noise;

// A key file named in the config: relative to the config's folder.
std::string beside(const std::string& config_path, const std::string& path) {
  if (path.empty() || path.front() == '/') return path;
  const size_t slash = config_path.rfind('/');
  return slash == std::string::npos ? path : config_path.substr(0, slash + 1) + path;
}

}  // namespace

bool secure_sessions(const LoadedConfig& cfg, Node::Options& options, std::string& error) {
  const config::NodeConfig& root = *cfg.root;
  const size_t listed = root.clients() ? root.clients()->size() : 0;
  if (root.key() == nullptr) {
    if (listed > 0) {
      error = cfg.path + ": \"clients\" without \"key\": a node accepts clients by key only with a key of its own";
      return false;
    }
    return true;
  }
  noise::KeyPair identity;
  std::string why;
  if (!noise::read_secret_key(beside(cfg.path, root.key()->str()), identity, why)) {
    error = cfg.path + ": key: " + why;
    return false;
  }
  if (listed == 0) {
    error = cfg.path + ": \"key\" without \"clients\": a secure node would refuse every client; list their public "
                       "keys (troupe keygen NAME writes NAME.pub)";
    return false;
  }
  std::vector<noise::Key> clients;
  for (size_t i = 0; i < listed; ++i) {
    const std::string entry = root.clients()->Get(static_cast<flatbuffers::uoffset_t>(i))->str();
    noise::Key key;
    if (!noise::parse_key_hex(entry, key) && !noise::read_public_key(beside(cfg.path, entry), key, why)) {
      error = cfg.path + ": clients[" + std::to_string(i) + "]: " + why;
      return false;
    }
    clients.push_back(key);
  }
  log_info("secure sessions: node key %s, %zu client key(s) accepted", noise::key_hex(identity.public_key).c_str(),
           clients.size());
  options.make_transport = [identity, clients]() -> std::unique_ptr<wire::Transport> {
    noise::SecureOptions o;
    o.role = noise::Role::Responder;
    o.identity = identity;
    o.accept = [clients](const noise::Key& client, std::string& refused) {
      if (std::find(clients.begin(), clients.end(), client) != clients.end()) return true;
      refused = "key " + noise::key_hex(client) + " is not among the node's clients";
      return false;
    };
    return std::make_unique<noise::NoiseTransport>(std::move(o));
  };
  return true;
}

}  // namespace troupe
