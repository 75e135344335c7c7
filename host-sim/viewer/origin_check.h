// Which WebSocket handshakes may open a bridge. The bridge gives full wire
// access to the node, so only the viewer's own page may use it: a browser
// lets any web page open a WebSocket to any address, and says which page
// it is in the Origin header. Two attacks are refused:
//   - a foreign page (Origin http://evil.example) opening ws://127.0.0.1:6680;
//   - DNS rebinding: evil.example's name pointed at 127.0.0.1, so the
//     browser takes the viewer for evil.example's own server (Origin and
//     Host both say evil.example:6680). The Host must be a name the viewer
//     is served under: an IP address, localhost or this machine's name.
// A client without Origin is not a browser (a browser always sends one on
// a WebSocket handshake) and could reach the node's port directly anyway.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace troupe::viewer {

struct OriginVerdict {
  bool allowed = false;
  /// Why it was refused (for the 403 and the log), empty when allowed.
  std::string why;
};

/// `host` and `origin` are the handshake's Host and Origin header values
/// (empty when absent). `allow_origins` are origins accepted whatever the
/// Host ("http://robots.lab:8080", e.g. behind a proxy), compared without
/// case and trailing slash. `machine_names` are names of this machine a
/// Host may use besides IP addresses and localhost.
OriginVerdict check_origin(std::string_view host, std::string_view origin,
                           const std::vector<std::string>& allow_origins,
                           const std::vector<std::string>& machine_names);

/// This machine's host name (gethostname), for check_origin().
std::vector<std::string> this_machine_names();

}  // namespace troupe::viewer
