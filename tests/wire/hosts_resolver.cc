#include "tests/wire/hosts_resolver.h"

#include <algorithm>
#include <sstream>

namespace troupe::testing {

wire::Resolver hosts_resolver(std::string hosts_text) {
  return [text = std::move(hosts_text)](const std::string& host, uint16_t port, std::vector<wire::Endpoint>& out,
                                        std::string& error) {
    out.clear();
    wire::Endpoint e;
    if (wire::parse_endpoint(host, port, e)) {
      out.push_back(e);
      return true;
    }
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
      std::istringstream words(line.substr(0, line.find('#')));
      std::string address, name;
      if (!(words >> address)) continue;
      while (words >> name) {
        if (name == host && wire::parse_endpoint(address, port, e)) out.push_back(e);
      }
    }
    // getaddrinfo's order for these lines (RFC 6724 puts ::1 first), which
    // the connection then keeps (RFC 8305 interleaving).
    std::stable_partition(out.begin(), out.end(),
                          [](const wire::Endpoint& a) { return a.addr.ss_family == AF_INET6; });
    if (out.empty()) error = "cannot resolve host '" + host + "': not in the test's hosts file";
    return !out.empty();
  };
}

}  // namespace troupe::testing
