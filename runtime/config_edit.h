// Node configs read and changed through their binary schema (what
// `flatc --schema -b` makes of config.fbs with a board's driver options),
// with no JSON parser: a board that reads only compiled configs still takes
// overrides on its command line (`troupe-node --set`) and shows what it runs
// (`--print-config`). The host's `troupe config` uses the same code with
// another board's schema.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace reflection {
struct Schema;
}

namespace troupe {

/// Changes one value of a node config. `config` holds a verified NodeConfig
/// buffer of `schema`; `assignment` is one of
///   INSTANCE.KEY=VALUE   option KEY of the driver instance INSTANCE (its
///                        "name", else its driver type)
///   KEY=VALUE            node setting KEY ("port", "listen", ...)
/// VALUE is checked against the field's type as the JSON parser checks a
/// config: an integer within its type's range, a finite number, true or
/// false, one of an enum's names; a string is taken as it is. Lists and
/// tables are changed in the config file, not here. On failure `config` is
/// unchanged and `error` says what is wrong and what exists instead.
bool set_config_value(const reflection::Schema& schema, std::vector<uint8_t>& config,
                      std::string_view assignment, std::string& error);

/// A node config as JSON that reads back as the same config: every number,
/// switch and enum with the value the node runs with (its schema default
/// when the config gives none), strings, lists and tables as the config
/// gives them, each driver instance with its options.
std::string config_to_json(const reflection::Schema& schema, const uint8_t* config);

}  // namespace troupe
