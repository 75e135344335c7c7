// Node configs: loading one (JSON or binary) and building a node from it,
// all or nothing.
#pragma once

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "runtime/config_generated.h"
#include "runtime/node.h"

namespace troupe {

/// A driver's typed options (its table in drivers/<d>/<d>.fbs), or the
/// schema's defaults when the config gave no "driver" object.
template <typename Options>
class OptionsView {
 public:
  explicit OptionsView(const DriverSetup& setup)
      : options_(setup.instance ? setup.instance->driver_as<Options>() : nullptr) {
    if (options_ == nullptr) {
      // An empty table reads back every field's default.
      empty_.Finish(flatbuffers::Offset<Options>(empty_.EndTable(empty_.StartTable())));
      options_ = flatbuffers::GetRoot<Options>(empty_.GetBufferPointer());
    }
  }
  const Options* operator->() const { return options_; }

 private:
  flatbuffers::FlatBufferBuilder empty_{64};
  const Options* options_;
};

/// A config read from a file. `root` points into `bytes`.
struct LoadedConfig {
  std::string path;
  std::vector<uint8_t> bytes;
  const config::NodeConfig* root = nullptr;
};

/// Reads the config at `path`: binary (as flatc -b makes it) on every board,
/// JSON where the board carries the parser. On failure `error` names the file
/// and the offending key or line.
bool load_config(const std::string& path, LoadedConfig& out, std::string& error);

/// Changes one value of a loaded config, "INSTANCE.KEY=VALUE" or
/// "KEY=VALUE" (runtime/config_edit.h), checked against this board's schema
/// as the config itself is. On failure `cfg` is unchanged and `error` says
/// what is wrong.
bool set_config_value(LoadedConfig& cfg, const char* assignment, std::string& error);

/// The config as JSON, every setting and option with the value the node
/// runs with (runtime/config_edit.h).
std::string config_to_json(const LoadedConfig& cfg);

/// Parses JSON text against the node config schema; false with `error`
/// ("path:line:col: what") when the board has no parser or the text is bad.
bool parse_config_json(const std::string& text, const std::string& path, std::vector<uint8_t>& binary,
                       std::string& error);

/// `path` as a file the config at `config_path` names: relative to the
/// config's folder unless absolute. Inline: the servers that read a config's
/// keys without its drivers (node_secure.h) link no driver table.
inline std::string config_relative(const std::string& config_path, const std::string& path) {
  if (path.empty() || path.front() == '/') return path;
  const size_t slash = config_path.rfind('/');
  return slash == std::string::npos ? path : config_path.substr(0, slash + 1) + path;
}

/// The node config file at `path` as it is, not yet verified: `binary` when
/// it is flatc's binary (the schema's identifier after the root offset),
/// else text for the caller to parse as JSON with its schema. False with
/// `error` naming the file when it cannot be read. Inline, as
/// config_relative: troupe-sim and troupe play read their --secure file
/// (secure_file.h) with it and link no driver table.
inline bool read_config_file(const std::string& path, std::vector<uint8_t>& bytes, bool& binary,
                             std::string& error) {
  FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) {
    error = path + ": cannot open: " + std::strerror(errno);
    return false;
  }
  bytes.clear();
  uint8_t chunk[4096];
  for (size_t n; (n = std::fread(chunk, 1, sizeof chunk, f)) > 0;) {
    bytes.insert(bytes.end(), chunk, chunk + n);
  }
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) {
    error = path + ": read error";
    return false;
  }
  // Compared by hand: GCC 12's -Werror build takes BufferHasIdentifier for
  // an overread.
  binary = bytes.size() >= 8 && std::memcmp(bytes.data() + 4, config::NodeConfigIdentifier(), 4) == 0;
  return true;
}

/// Node::Options as the config sets them.
Node::Options node_options(const config::NodeConfig& cfg);

/// Registers every instance's devices, then creates and sets up each driver
/// in order. On the first failure returns false, `error` naming the file, the
/// instance and the problem, and `failure` (when given) whether a driver
/// found its hardware missing; the caller must not start the node.
bool build_node(Node& node, const LoadedConfig& cfg, std::string& error, SetupFailure* failure = nullptr);

/// Names of the drivers compiled into this board, comma-separated.
std::string board_driver_names();

}  // namespace troupe
