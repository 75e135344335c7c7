// JSON node configs, parsed against a binary node config schema with
// FlatBuffers' parser: troupe-node on the boards that read JSON (host,
// desktop), and `troupe config compile` for any board.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace troupe {

/// Parses JSON `text` against `schema` (flatc --schema -b of config.fbs
/// with board `board`'s driver options; `board_drivers` lists them, for the
/// message when the text names another driver). On success `binary` holds
/// the config as `flatc -b` makes it; otherwise false with `error`
/// ("path:line:col: what", path as given).
bool parse_node_config_json(const uint8_t* schema, size_t schema_size, const char* board,
                            const std::string& board_drivers, const std::string& text,
                            const std::string& path, std::vector<uint8_t>& binary, std::string& error);

}  // namespace troupe
