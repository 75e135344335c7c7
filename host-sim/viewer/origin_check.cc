#include "host-sim/viewer/origin_check.h"

#include <unistd.h>

#include <boost/asio/ip/address.hpp>
#include <cctype>

namespace troupe::viewer {
namespace {

bool same_text(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i])))
      return false;
  }
  return true;
}

std::string_view trim_slash(std::string_view s) {
  while (!s.empty() && s.back() == '/') s.remove_suffix(1);
  return s;
}

// The name part of a Host value: "[::1]:6680" gives "::1", "a.b:80" "a.b".
std::string_view host_name(std::string_view host) {
  if (!host.empty() && host.front() == '[') {
    const size_t close = host.find(']');
    return close == std::string_view::npos ? std::string_view() : host.substr(1, close - 1);
  }
  const size_t colon = host.find(':');
  std::string_view name = colon == std::string_view::npos ? host : host.substr(0, colon);
  if (!name.empty() && name.back() == '.') name.remove_suffix(1);  // "localhost." is localhost
  return name;
}

bool is_ip_address(std::string_view name) {
  boost::system::error_code ec;
  boost::asio::ip::make_address(std::string(name), ec);
  return !ec;
}

}  // namespace

OriginVerdict check_origin(std::string_view host, std::string_view origin,
                           const std::vector<std::string>& allow_origins,
                           const std::vector<std::string>& machine_names) {
  for (const std::string& allowed : allow_origins) {
    if (!origin.empty() && same_text(trim_slash(origin), trim_slash(allowed))) return {true, {}};
  }
  const std::string_view name = host_name(host);
  bool ours = !name.empty() && (same_text(name, "localhost") || is_ip_address(name));
  for (const std::string& m : machine_names) ours = ours || same_text(name, m);
  if (!ours) {
    return {false, "Host '" + std::string(host) +
                       "' is not an address or a name of this machine (DNS rebinding?); "
                       "--view-allow-origin ORIGIN accepts a page served under another name"};
  }
  if (origin.empty()) return {true, {}};
  if (!same_text(trim_slash(origin), "http://" + std::string(host))) {
    return {false, "a page from '" + std::string(origin) +
                       "' may not use this viewer (its own pages are http://" + std::string(host) +
                       "); --view-allow-origin ORIGIN accepts another"};
  }
  return {true, {}};
}

std::vector<std::string> this_machine_names() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0 || name[0] == '\0') return {};
  return {name};
}

}  // namespace troupe::viewer
