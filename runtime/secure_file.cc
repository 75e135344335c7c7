#include "runtime/secure_file.h"

#include <vector>

#include "flatbuffers/reflection_generated.h"
#include "runtime/config_generated.h"
#include "runtime/config_json.h"
#include "runtime/node_config.h"

// The node config schema (flatc --schema -b), embedded at build time.
extern const unsigned char troupe_config_bfbs[];
extern const unsigned troupe_config_bfbs_size;

namespace troupe {

bool load_secure_sessions(const std::string& path, SecureSessions& out, std::string& error) {
  std::vector<uint8_t> bytes;
  bool binary = false;
  if (!read_config_file(path, bytes, binary, error)) return false;
  if (!binary) {
    std::vector<uint8_t> parsed;
    if (!parse_node_config_json(troupe_config_bfbs, troupe_config_bfbs_size, "host", "none",
                                std::string(bytes.begin(), bytes.end()), path, parsed, error)) {
      return false;
    }
    bytes = std::move(parsed);
  }
  flatbuffers::Verifier verifier(bytes.data(), bytes.size());
  if (!config::VerifyNodeConfigBuffer(verifier)) {
    error = path + ": not a valid node config (the FlatBuffers verifier refused it)";
    return false;
  }
  // Anything else a node config sets would be ignored here: say so rather
  // than serve on another port or address than the file seems to ask.
  const flatbuffers::Table* table = flatbuffers::GetRoot<flatbuffers::Table>(bytes.data());
  for (const reflection::Field* field : *reflection::GetSchema(troupe_config_bfbs)->root_table()->fields()) {
    const std::string name = field->name()->str();
    if (name == "key" || name == "clients" || !table->CheckField(field->offset())) continue;
    error = path + ": \"" + name +
            "\": this file holds only \"key\" and \"clients\"; the rest is set on the command line";
    return false;
  }
  const config::NodeConfig& root = *config::GetNodeConfig(bytes.data());
  if (root.key() == nullptr) {
    error =
        path + ": no \"key\": secure sessions need this server's secret key (troupe keygen NAME writes one)";
    return false;
  }
  return secure_sessions(root, path, out, error);
}

const char kSecureFlagHelp[] =
    "serve secure sessions only (wire/README.md, \"Secure sessions\"):\n"
    "FILE is JSON with this server's secret key and the clients it\n"
    "accepts, with their rights, written as in a node config, so a\n"
    "node's block is copied as it is: {\"key\": \"sim\", \"clients\":\n"
    "[{\"key\": \"laptop.pub\", \"read\": [\"*\"]}]} (paths relative to FILE)";

}  // namespace troupe
