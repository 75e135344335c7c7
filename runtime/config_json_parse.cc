#include <cstdio>

#include "flatbuffers/idl.h"
#include "runtime/config_json.h"

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

bool parse_node_config_json(const uint8_t* schema, size_t schema_size, const char* board,
                            const std::string& board_drivers, const std::string& text,
                            const std::string& path, std::vector<uint8_t>& binary, std::string& error) {
  flatbuffers::IDLOptions opts;
  opts.skip_unexpected_fields_in_json = false;  // an unknown key is an error
  flatbuffers::Parser parser(opts);
  if (!parser.Deserialize(schema, schema_size)) {
    error = "internal: the embedded config schema does not load";
    return false;
  }
  if (!parser.Parse(text.c_str(), nullptr, path.c_str())) {
    // The parser says "FILE:LINE: COL: error: WHAT" (FILE made absolute);
    // say "path:LINE:COL: WHAT" with the path as the user gave it.
    const std::string& msg = parser.error_;
    size_t at = msg.find(": error: ");
    std::string what = at == std::string::npos ? msg : msg.substr(at + 9);
    while (!what.empty() && what.back() == '\n') what.pop_back();
    unsigned line = 0, col = 0;
    size_t col_at = at == std::string::npos ? std::string::npos : msg.rfind(": ", at - 1);
    size_t line_at = col_at == std::string::npos ? std::string::npos : msg.rfind(':', col_at - 1);
    std::string where = path;
    if (line_at != std::string::npos && sscanf(msg.c_str() + line_at, ":%u: %u", &line, &col) == 2) {
      where += ":" + std::to_string(line) + ":" + std::to_string(col);
    }
    // A driver type the union does not have is a driver this board lacks.
    const std::string unknown = "unknown enum value: ";
    if (what.starts_with(unknown) && line_mentions(text, line, "driver_type")) {
      error = where + ": driver '" + what.substr(unknown.size()) + "' is not compiled into board " + board +
              " (its drivers: " + board_drivers + ")";
    } else {
      error = where + ": " + what;
    }
    return false;
  }
  const uint8_t* data = parser.builder_.GetBufferPointer();
  binary.assign(data, data + parser.builder_.GetSize());
  return true;
}

}  // namespace troupe
