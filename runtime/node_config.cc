#include "runtime/node_config.h"

#include <cstdio>
#include <cstring>
#include <memory>

#include "flatbuffers/reflection_generated.h"
#include "runtime/config_edit.h"
#include "runtime/log.h"
#include "wire/address.h"

// This board's node config schema (flatc --schema -b), embedded at build time.
extern const unsigned char troupe_config_bfbs[];

namespace troupe {
namespace {

const reflection::Schema& board_schema() { return *reflection::GetSchema(troupe_config_bfbs); }

// One call site of the verifier, whose code is large for a board.
bool verified(const std::vector<uint8_t>& bytes) {
  flatbuffers::Verifier verifier(bytes.data(), bytes.size());
  return config::VerifyNodeConfigBuffer(verifier);
}

const DriverEntry* find_driver(const char* name) {
  for (const DriverEntry* const* e = kBoardDrivers; *e != nullptr; ++e) {
    if (strcmp((*e)->name, name) == 0) return *e;
  }
  return nullptr;
}

// "drivers[2] (kinematic)": where a problem is, for error messages.
std::string where(const std::string& path, size_t i, const std::string& name) {
  return path + ": drivers[" + std::to_string(i) + "] (" + name + ")";
}

bool parse_address(const char* text, wire::Address& out, std::string& error) {
  wire::DeviceSpec spec;
  if (!wire::parse_device(text, spec, error)) return false;
  int robot = wire::robot_number(spec.robot);
  if (robot < 0) {
    error = "device '" + std::string(text) + "': a node names robots by number (robot names are troupe-sim's)";
    return false;
  }
  out = wire::Address(uint16_t(robot), uint16_t(spec.iface), spec.index);
  return true;
}

}  // namespace

std::string board_driver_names() {
  std::string names;
  for (const DriverEntry* const* e = kBoardDrivers; *e != nullptr; ++e) {
    if (!names.empty()) names += ", ";
    names += (*e)->name;
  }
  return names.empty() ? "none" : names;
}

bool load_config(const std::string& path, LoadedConfig& out, std::string& error) {
  out = LoadedConfig{};
  out.path = path;
  std::vector<uint8_t> raw;
  bool binary = false;
  if (!read_config_file(path, raw, binary, error)) return false;
  if (binary) {
    out.bytes = std::move(raw);
  } else if (!parse_config_json(std::string(raw.begin(), raw.end()), path, out.bytes, error)) {
    return false;
  }
  if (!verified(out.bytes)) {
    error = path + ": not a valid node config (the FlatBuffers verifier refused it)";
    return false;
  }
  out.root = config::GetNodeConfig(out.bytes.data());
  return true;
}

bool set_config_value(LoadedConfig& cfg, const char* assignment, std::string& error) {
  std::vector<uint8_t> bytes = cfg.bytes;
  if (!set_config_value(board_schema(), bytes, assignment, error)) return false;
  if (!verified(bytes)) {
    error = "internal: the changed config does not verify";
    return false;
  }
  cfg.bytes = std::move(bytes);
  cfg.root = config::GetNodeConfig(cfg.bytes.data());
  return true;
}

std::string config_to_json(const LoadedConfig& cfg) { return config_to_json(board_schema(), cfg.bytes.data()); }

Node::Options node_options(const config::NodeConfig& cfg) {
  Node::Options o;
  if (cfg.name()) o.name = cfg.name()->str();
  if (cfg.listen()) o.listen = cfg.listen()->str();
  o.port = cfg.port();
  o.udp = cfg.udp();
  o.max_clients = cfg.max_clients();
  o.client_queue_bytes = cfg.client_queue_bytes();
  o.limits.max_frame_bytes = cfg.max_frame_bytes();
  o.request_timeout_ms = cfg.request_timeout_ms();
  o.socket_send_bytes = cfg.socket_send_bytes();
  o.max_clients_per_address = cfg.max_clients_per_address();
  o.hello_timeout_ms = cfg.hello_timeout_ms();
  o.idle_timeout_ms = cfg.idle_timeout_ms();
  return o;
}

bool build_node(Node& node, const LoadedConfig& cfg, std::string& error, SetupFailure* failure) {
  const auto* instances = cfg.root->drivers();
  if (instances == nullptr || instances->size() == 0) {
    log_warn("%s: no drivers: the node serves no devices", cfg.path.c_str());
    return true;
  }
  struct Planned {
    const DriverEntry* entry;
    std::string name;
    std::vector<DeviceId> provides;
    std::vector<DeviceId> required;
  };
  std::vector<Planned> plan(instances->size());
  std::vector<std::unique_ptr<Driver>> created(instances->size());

  // Pass 1: create every instance and register what it provides, so that
  // "uses" may name devices of instances listed later.
  for (size_t i = 0; i < instances->size(); ++i) {
    const config::DriverInstance* inst = instances->Get(flatbuffers::uoffset_t(i));
    const char* type = config::EnumNameDriverOptions(inst->driver_type());
    if (inst->driver_type() == config::DriverOptions::NONE) {
      error = cfg.path + ": drivers[" + std::to_string(i) + "]: no \"driver_type\" (board " + kBoardName +
              " has: " + board_driver_names() + ")";
      return false;
    }
    Planned& p = plan[i];
    p.entry = find_driver(type);
    p.name = inst->name() ? inst->name()->str() : std::string(type);
    if (p.entry == nullptr) {
      error = where(cfg.path, i, p.name) + ": driver '" + type + "' is not compiled into board " + kBoardName;
      return false;
    }
    created[i].reset(p.entry->create());
    if (inst->provides() == nullptr || inst->provides()->size() == 0) {
      error = where(cfg.path, i, p.name) + ": \"provides\" lists no device";
      return false;
    }
    for (flatbuffers::uoffset_t k = 0; k < inst->provides()->size(); ++k) {
      const char* text = inst->provides()->Get(k)->c_str();
      wire::Address addr;
      std::string why;
      if (!parse_address(text, addr, why)) {
        error = where(cfg.path, i, p.name) + ": provides[" + std::to_string(k) + "]: " + why;
        return false;
      }
      DeviceId id = node.add_device(addr, created[i].get(), p.name);
      if (id == kNoDevice) {
        error = where(cfg.path, i, p.name) + ": provides[" + std::to_string(k) + "]: " + text +
                " is already provided by another driver";
        return false;
      }
      p.provides.push_back(id);
    }
  }
  // Pass 2: resolve "uses", then set drivers up in order.
  for (size_t i = 0; i < instances->size(); ++i) {
    const config::DriverInstance* inst = instances->Get(flatbuffers::uoffset_t(i));
    Planned& p = plan[i];
    if (inst->uses()) {
      for (flatbuffers::uoffset_t k = 0; k < inst->uses()->size(); ++k) {
        const char* text = inst->uses()->Get(k)->c_str();
        wire::Address addr;
        std::string why;
        if (!parse_address(text, addr, why)) {
          error = where(cfg.path, i, p.name) + ": uses[" + std::to_string(k) + "]: " + why;
          return false;
        }
        DeviceId id = node.find_device(addr);
        if (id == kNoDevice) {
          error = where(cfg.path, i, p.name) + ": uses " + text + ", which no driver provides";
          return false;
        }
        p.required.push_back(id);
      }
    }
    DriverSetup setup;
    setup.instance = inst;
    setup.name = p.name;
    setup.provides = p.provides;
    setup.required = p.required;
    setup.config_path = cfg.path;
    std::string why;
    if (!node.add_driver(std::move(created[i]), setup, why, failure)) {
      error = where(cfg.path, i, p.name) + ": " + why;
      return false;
    }
    log_info("%s: %s ready", cfg.path.c_str(), p.name.c_str());
  }
  return true;
}

}  // namespace troupe
