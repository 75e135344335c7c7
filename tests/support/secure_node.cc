#include "tests/support/secure_node.h"

#include <fstream>

namespace troupe::testing {
namespace {

const std::string kBin = std::string(TROUPE_BINARY_DIR) + "/bin";
// Hang guard for keygen, ms.
constexpr int kRunMs = 30'000;

}  // namespace

bool SecureNodeProcess::make_keys(const std::vector<std::string>& keys, std::string& error) {
  dir_ = make_temp_dir("troupe-secure-");
  if (dir_.empty()) {
    error = "no scratch folder";
    return false;
  }
  std::vector<std::string> names = keys;
  names.insert(names.begin(), "node");
  for (const std::string& name : names) {
    ProgramResult r = run_to_end({kBin + "/troupe", "keygen", path(name)}, kRunMs);
    if (r.status != 0) {
      error = "troupe keygen " + name + ": " + r.err;
      return false;
    }
  }
  return true;
}

bool SecureNodeProcess::start(const std::string& clients, const std::string& drivers, std::string& error) {
  port_ = free_port();
  const std::string config = path("node.json");
  std::ofstream(config) << R"({ "name": "secure-robot", "listen": "127.0.0.1", "port": )" << port_
                        << R"(, "key": "node", "clients": )" << clients << R"(, "drivers": )" << drivers
                        << " }";
  if (!node_.start({kBin + "/troupe-node", config}, dir_, "troupe-node", error)) return false;
  if (!wait_for_listener(port_, 10)) {
    error = "troupe-node did not start: " + node_.err();
    return false;
  }
  return true;
}

SecureNodeProcess::~SecureNodeProcess() {
  if (node_.running()) node_.stop();
  if (!dir_.empty()) remove_tree(dir_);
}

std::string SecureNodeProcess::node_key_hex() const {
  std::string tag, key;
  std::ifstream(path("node.pub")) >> tag >> key;
  return key;
}

std::vector<std::string> secure_args(const SecureNodeProcess& node, const std::string& identity,
                                     const std::string& node_key) {
  return {"--identity", node.path(identity), "--node-key", node.path(node_key)};
}

}  // namespace troupe::testing
