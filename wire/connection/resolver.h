// Turning "HOST" into the socket addresses a connection tries, in order. The
// connection core asks for this (ActionKind::Resolve) and never does it
// itself; the adapters call a Resolver, which tests replace (for example with
// a hosts file where localhost is ::1 first, as on a standard Debian 12).
#pragma once

#include <sys/socket.h>

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace troupe::wire {

/// One address to connect to.
struct Endpoint {
  sockaddr_storage addr{};
  socklen_t len = 0;
  /// "127.0.0.1:6665", "[::1]:6665".
  std::string text() const;
};

/// Looks up `host` (a name or a numeric address, IPv6 with or without
/// brackets) for TCP `port`: the addresses to try, in order. False with
/// `error` ("cannot resolve host 'x': ...") when there are none.
using Resolver = std::function<bool(const std::string& host, uint16_t port, std::vector<Endpoint>& out,
                                    std::string& error)>;

/// The system's resolver (getaddrinfo: hosts file, DNS), in the order
/// RFC 8305 asks for. Blocks while DNS answers.
bool resolve_system(const std::string& host, uint16_t port, std::vector<Endpoint>& out, std::string& error);

/// Numeric addresses and `localhost` only, so it never waits on DNS: for a
/// node's event loop, which must not block. A name is refused with `error`.
bool resolve_numeric(const std::string& host, uint16_t port, std::vector<Endpoint>& out, std::string& error);

/// An endpoint for a numeric IPv4 or IPv6 address (brackets allowed).
bool parse_endpoint(std::string_view address, uint16_t port, Endpoint& out);

/// RFC 8305 section 4: alternates address families, starting with the
/// family of the first address; keeps the order within each family.
void interleave_families(std::vector<Endpoint>& endpoints);

}  // namespace troupe::wire
