#include "host-sim/viewer/access_token.h"

#include <sys/random.h>

#include <cstdint>
#include <cstdio>

namespace troupe::viewer {
namespace {

// The value of `name` in a list of `name=value` pairs split by `sep`
// (a query's '&', a Cookie header's ';'), spaces around pairs skipped.
std::string_view find_value(std::string_view list, std::string_view name, char sep) {
  while (!list.empty()) {
    const size_t end = list.find(sep);
    std::string_view pair = list.substr(0, end);
    while (!pair.empty() && pair.front() == ' ') pair.remove_prefix(1);
    if (pair.size() > name.size() && pair.substr(0, name.size()) == name && pair[name.size()] == '=') {
      return pair.substr(name.size() + 1);
    }
    if (end == std::string_view::npos) break;
    list.remove_prefix(end + 1);
  }
  return {};
}

}  // namespace

std::string make_token() {
  uint8_t bytes[16] = {};
  size_t got = 0;
  while (got < sizeof bytes) {
    const ssize_t n = getrandom(bytes + got, sizeof bytes - got, 0);
    if (n > 0) got += size_t(n);
  }
  std::string hex;
  char two[3];
  for (uint8_t b : bytes) {
    std::snprintf(two, sizeof two, "%02x", b);
    hex += two;
  }
  return hex;
}

std::string presented_token(std::string_view target, std::string_view cookie_header) {
  if (const size_t q = target.find('?'); q != std::string_view::npos) {
    std::string_view query = target.substr(q + 1);
    if (const size_t hash = query.find('#'); hash != std::string_view::npos) query = query.substr(0, hash);
    const std::string_view v = find_value(query, "token", '&');
    if (!v.empty()) return std::string(v);
  }
  return std::string(find_value(cookie_header, kTokenCookie, ';'));
}

bool token_matches(std::string_view presented, std::string_view token) {
  if (token.empty() || presented.size() != token.size()) return false;
  uint8_t diff = 0;
  for (size_t i = 0; i < token.size(); ++i) diff |= uint8_t(presented[i] ^ token[i]);
  return diff == 0;
}

}  // namespace troupe::viewer
