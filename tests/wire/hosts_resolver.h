// A resolver that reads hosts-file text instead of the system's: tests give
// `localhost` the addresses a standard Debian 12 /etc/hosts gives it (::1
// first), whatever the machine running them has.
#pragma once

#include <string>

#include "wire/connection/resolver.h"

namespace troupe::testing {

/// Lines "ADDRESS NAME..." ('#' starts a comment); a host resolves to the
/// addresses of the lines naming it, IPv6 first as getaddrinfo ranks them
/// (RFC 6724 puts ::1 above 127.0.0.1), and numeric hosts to themselves.
wire::Resolver hosts_resolver(std::string hosts_text);

/// /etc/hosts of a fresh Debian 12 install: localhost is ::1 and 127.0.0.1.
inline constexpr const char* kDebianHosts =
    "127.0.0.1\tlocalhost\n"
    "::1\t\tlocalhost ip6-localhost ip6-loopback\n";

}  // namespace troupe::testing
