// JSON node configs, for boards that carry the FlatBuffers parser (host,
// desktop). The schema travels inside the binary as flatc's binary schema.
#include "runtime/config_json.h"

#include "runtime/node_config.h"

extern const unsigned char troupe_config_bfbs[];
extern const unsigned troupe_config_bfbs_size;

namespace troupe {

bool parse_config_json(const std::string& text, const std::string& path, std::vector<uint8_t>& binary,
                       std::string& error) {
  return parse_node_config_json(troupe_config_bfbs, troupe_config_bfbs_size, kBoardName, board_driver_names(),
                                text, path, binary, error);
}

}  // namespace troupe
