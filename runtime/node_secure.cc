#include "runtime/node_secure.h"

#include <algorithm>
#include <memory>
#include <unordered_map>
#include <utility>

#include "runtime/node_config.h"
#include "wire/noise/key_file.h"
#include "wire/noise/noise_transport.h"

namespace troupe {
namespace {

namespace noise = wire::noise;

// The rights a client's entry grants: everything when it lists none.
bool client_rights(const config::TrustedClient& entry, std::shared_ptr<const Rights>& out, std::string& error) {
  const std::pair<Right, const flatbuffers::Vector<flatbuffers::Offset<flatbuffers::String>>*> lists[] = {
      {Right::Read, entry.read()}, {Right::Command, entry.command()}, {Right::Request, entry.request()}};
  if (!entry.read() && !entry.command() && !entry.request()) {
    out = std::make_shared<const PatternRights>(PatternRights::all());
    return true;
  }
  auto rights = std::make_shared<PatternRights>();
  for (const auto& [right, patterns] : lists) {
    if (patterns == nullptr) continue;
    for (const flatbuffers::String* text : *patterns) {
      DevicePattern p;
      if (!DevicePattern::parse(text->string_view(), p, error)) {
        error = std::string(right_name(right)) + ": " + error;
        return false;
      }
      rights->grant(right, std::move(p));
    }
  }
  out = std::move(rights);
  return true;
}

}  // namespace

bool secure_sessions(const config::NodeConfig& root, const std::string& config_path, SecureSessions& out,
                     std::string& error) {
  out = SecureSessions{};
  const size_t listed = root.clients() ? root.clients()->size() : 0;
  if (root.key() == nullptr) {
    if (listed > 0) {
      error = config_path +
              ": \"clients\" without \"key\": a node accepts clients by key only with a key of its own";
      return false;
    }
    return true;
  }
  noise::KeyPair identity;
  std::string why;
  if (!noise::read_secret_key(config_relative(config_path, root.key()->str()), identity, why)) {
    error = config_path + ": key: " + why;
    return false;
  }
  if (listed == 0) {
    error = config_path +
            ": \"key\" without \"clients\": a secure node would refuse every client; list their public "
            "keys (troupe keygen NAME writes NAME.pub)";
    return false;
  }
  std::vector<noise::Key> clients;
  // Keyed by the hex text the transport names its peer by.
  auto rights = std::make_shared<std::unordered_map<std::string, std::shared_ptr<const Rights>>>();
  for (size_t i = 0; i < listed; ++i) {
    const config::TrustedClient& entry = *root.clients()->Get(static_cast<flatbuffers::uoffset_t>(i));
    const std::string where = config_path + ": clients[" + std::to_string(i) + "]";
    noise::Key key;
    const std::string key_text = entry.key()->str();  // required: the verifier saw it
    if (!noise::parse_key_hex(key_text, key) &&
        !noise::read_public_key(config_relative(config_path, key_text), key, why)) {
      error = where + ": " + why;
      return false;
    }
    std::shared_ptr<const Rights> granted;
    if (!client_rights(entry, granted, why)) {
      error = where + ": " + why;
      return false;
    }
    clients.push_back(key);
    (*rights)[noise::key_hex(key)] = granted;
  }
  out.key_hex = noise::key_hex(identity.public_key);
  out.make_transport = [identity, clients]() -> std::unique_ptr<wire::Transport> {
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
  out.rights_of = [rights](const std::string& peer) -> std::shared_ptr<const Rights> {
    auto it = rights->find(peer);
    return it == rights->end() ? std::make_shared<const PatternRights>() : it->second;  // unknown: nothing
  };
  return true;
}

bool secure_sessions(const LoadedConfig& cfg, Node::Options& options, std::string& error) {
  SecureSessions sessions;
  if (!secure_sessions(*cfg.root, cfg.path, sessions, error)) return false;
  if (sessions.on()) sessions.apply(options);
  return true;
}

}  // namespace troupe
