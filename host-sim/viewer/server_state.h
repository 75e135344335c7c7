// What the viewer server's sessions share. Touched only on the server's
// asio thread.
#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "host-sim/viewer/view_server.h"
#include "wire/noise/noise_transport.h"

namespace troupe::viewer {

struct ServerState {
  ViewOptions options;
  /// The node's addresses, resolved once at open().
  boost::asio::ip::tcp::resolver::results_type node;
  /// A secure node's session options, each page's session a copy; nullptr:
  /// plain TCP.
  std::shared_ptr<const wire::noise::SecureOptions> secure;
  /// WebSockets open now.
  uint32_t sessions = 0;
  /// This machine's names, which a page's Host may use (origin_check.h).
  std::vector<std::string> machine_names;
  /// WebSocket handshakes refused for their Origin or Host so far.
  uint64_t refused_origins = 0;
  /// Requests refused for want of the token so far.
  uint64_t refused_tokens = 0;
};

}  // namespace troupe::viewer
