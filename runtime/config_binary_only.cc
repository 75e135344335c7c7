// Board builds carry no JSON parser: their configs are compiled by flatc at
// build time (see boards/<board>/board.cmake, BOARD_CONFIG_FORMAT binary).
#include "runtime/node_config.h"

namespace troupe {

bool parse_config_json(const std::string& /*text*/, const std::string& path, std::vector<uint8_t>& /*binary*/,
                       std::string& error) {
  error = path + ": board " + std::string(kBoardName) +
          " reads binary node configs only; use the .bin flatc made from the JSON at build time";
  return false;
}

}  // namespace troupe
