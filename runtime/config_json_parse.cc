#include <cstdio>
#include <string_view>

#include "flatbuffers/idl.h"
#include "runtime/config_json.h"

namespace troupe {
namespace {

// True when line `line` (1-based) of `text` sets "driver_type" to `value`:
// the parser names an unknown enum value without the key it was for, and
// only an unknown driver type means a driver the board lacks (an option's
// bad enum value, on the same line of a one-line config, does not).
bool line_sets_driver_type(const std::string& text, unsigned line, const std::string& value) {
  size_t begin = 0;
  for (unsigned l = 1; l < line && begin != std::string::npos; ++l) {
    begin = text.find('\n', begin);
    if (begin != std::string::npos) ++begin;
  }
  if (begin == std::string::npos) return false;
  size_t end = text.find('\n', begin);
  const std::string_view row =
      std::string_view(text).substr(begin, end == std::string::npos ? end : end - begin);
  const std::string_view key = "\"driver_type\"";
  for (size_t at = row.find(key); at != std::string_view::npos; at = row.find(key, at + 1)) {
    size_t v = at + key.size();
    while (v < row.size() && (row[v] == ' ' || row[v] == '\t' || row[v] == ':')) ++v;
    if (row.substr(v).starts_with("\"" + value + "\"")) return true;
  }
  return false;
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
    const std::string value = what.starts_with(unknown) ? what.substr(unknown.size()) : "";
    if (!value.empty() && line_sets_driver_type(text, line, value)) {
      error = where + ": driver '" + value + "' is not compiled into board " + board +
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
