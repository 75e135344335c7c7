#include "wire/connection/resolver.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>

#include <cstring>

namespace troupe::wire {
namespace {

std::string strip_brackets(std::string_view host) {
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  return std::string(host);
}

bool lookup(const std::string& host, uint16_t port, std::vector<Endpoint>& out, std::string& error) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_NUMERICSERV;
  addrinfo* found = nullptr;
  std::string name = strip_brackets(host);
  if (int rc = getaddrinfo(name.c_str(), std::to_string(port).c_str(), &hints, &found); rc != 0) {
    error = "cannot resolve host '" + host + "': " + gai_strerror(rc);
    return false;
  }
  out.clear();
  for (addrinfo* ai = found; ai != nullptr; ai = ai->ai_next) {
    if (ai->ai_addrlen > sizeof(sockaddr_storage)) continue;
    Endpoint e;
    std::memcpy(&e.addr, ai->ai_addr, ai->ai_addrlen);
    e.len = socklen_t(ai->ai_addrlen);
    out.push_back(e);
  }
  freeaddrinfo(found);
  interleave_families(out);
  if (out.empty()) error = "cannot resolve host '" + host + "': no address";
  return !out.empty();
}

}  // namespace

std::string Endpoint::text() const {
  char ip[INET6_ADDRSTRLEN] = "?";
  if (addr.ss_family == AF_INET6) {
    const auto* a = reinterpret_cast<const sockaddr_in6*>(&addr);
    inet_ntop(AF_INET6, &a->sin6_addr, ip, sizeof ip);
    return "[" + std::string(ip) + "]:" + std::to_string(ntohs(a->sin6_port));
  }
  const auto* a = reinterpret_cast<const sockaddr_in*>(&addr);
  inet_ntop(AF_INET, &a->sin_addr, ip, sizeof ip);
  return std::string(ip) + ":" + std::to_string(ntohs(a->sin_port));
}

bool parse_endpoint(std::string_view address, uint16_t port, Endpoint& out) {
  std::string ip = strip_brackets(address);
  out = Endpoint{};
  auto* v4 = reinterpret_cast<sockaddr_in*>(&out.addr);
  auto* v6 = reinterpret_cast<sockaddr_in6*>(&out.addr);
  if (inet_pton(AF_INET, ip.c_str(), &v4->sin_addr) == 1) {
    v4->sin_family = AF_INET;
    v4->sin_port = htons(port);
    out.len = sizeof(sockaddr_in);
    return true;
  }
  if (inet_pton(AF_INET6, ip.c_str(), &v6->sin6_addr) == 1) {
    v6->sin6_family = AF_INET6;
    v6->sin6_port = htons(port);
    out.len = sizeof(sockaddr_in6);
    return true;
  }
  return false;
}

void interleave_families(std::vector<Endpoint>& endpoints) {
  if (endpoints.empty()) return;
  sa_family_t first = endpoints.front().addr.ss_family;
  std::vector<Endpoint> mine, other;
  for (const Endpoint& e : endpoints) (e.addr.ss_family == first ? mine : other).push_back(e);
  endpoints.clear();
  for (size_t i = 0; i < mine.size() || i < other.size(); ++i) {
    if (i < mine.size()) endpoints.push_back(mine[i]);
    if (i < other.size()) endpoints.push_back(other[i]);
  }
}

bool resolve_system(const std::string& host, uint16_t port, std::vector<Endpoint>& out, std::string& error) {
  Endpoint e;
  if (parse_endpoint(host, port, e)) {  // no lookup at all for an address
    out.assign(1, e);
    return true;
  }
  return lookup(host, port, out, error);
}

bool resolve_numeric(const std::string& host, uint16_t port, std::vector<Endpoint>& out, std::string& error) {
  Endpoint e;
  if (parse_endpoint(host, port, e)) {
    out.assign(1, e);
    return true;
  }
  // localhost is answered from the hosts file, never by DNS (RFC 6761).
  if (host == "localhost") return lookup(host, port, out, error);
  error = "host '" + host +
          "' is not a numeric address (a name needs DNS, which would block the node's loop; resolve it first)";
  return false;
}

}  // namespace troupe::wire
