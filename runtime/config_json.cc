// JSON node configs, for boards that carry the FlatBuffers parser (host,
// desktop). The schema travels inside the binary as flatc's binary schema.
#include <cstdio>
#include <string>

#include "flatbuffers/idl.h"
#include "runtime/node_config.h"

extern const unsigned char troupe_config_bfbs[];
extern const unsigned troupe_config_bfbs_size;

namespace troupe {
namespace {

bool line_mentions(const std::string& text, unsigned line, const char* word) {
  size_t begin = 0;
  for (unsigned l = 1; l < line && begin != std::string::npos; ++l) {
    begin = text.find('\n', begin);
    if (begin != std::string::npos) ++begin;
  }
  if (begin == std::string::npos) return false;
  size_t end = text.find('\n', begin);
  return text.substr(begin, end == std::string::npos ? end : end - begin).find(word) != std::string::npos;
}

}  // namespace

bool parse_config_json(const std::string& text, const std::string& path, std::vector<uint8_t>& binary,
                       std::string& error) {
  flatbuffers::IDLOptions opts;
  opts.skip_unexpected_fields_in_json = false;  // an unknown key is an error
  flatbuffers::Parser parser(opts);
  if (!parser.Deserialize(troupe_config_bfbs, troupe_config_bfbs_size)) {
    error = "internal: the embedded config schema does not load";
    return false;
  }
  if (!parser.Parse(text.c_str(), nullptr, path.c_str())) {
    // The parser says "FILE:LINE: COL: error: WHAT" (FILE made absolute);
    // say "path:LINE:COL: WHAT" with the path as the user gave it.
    const std::string& msg = parser.error_;
    size_t at = msg.find(": error: ");
    std::string what = at == std::string::npos ? msg : msg.substr(at + 9);
    unsigned line = 0, col = 0;
    size_t col_at = at == std::string::npos ? std::string::npos : msg.rfind(": ", at - 1);
    size_t line_at = col_at == std::string::npos ? std::string::npos : msg.rfind(':', col_at - 1);
    if (line_at != std::string::npos && sscanf(msg.c_str() + line_at, ":%u: %u", &line, &col) == 2) {
      error = path + ":" + std::to_string(line) + ":" + std::to_string(col) + ": " + what;
    } else {
      error = path + ": " + msg;
    }
    if (what.find("unknown enum value") != std::string::npos && line_mentions(text, line, "driver_type")) {
      error += " (drivers compiled into board " + std::string(kBoardName) + ": " + board_driver_names() + ")";
    }
    return false;
  }
  const uint8_t* data = parser.builder_.GetBufferPointer();
  binary.assign(data, data + parser.builder_.GetSize());
  return true;
}

}  // namespace troupe
