// The browser viewer's server: HTTP for the page's files and, on /ws, a
// WebSocket bridge to a node's TCP port. The page speaks the wire protocol
// itself: one binary WebSocket message is one frame (prefix included), and
// each WebSocket gets its own TCP connection to the node, so the node sees
// the page as one more client. Only the viewer's own page may open one
// (origin_check.h). Frames from the page are verified on the way
// in; a bad one closes that WebSocket (code 1007, the reason in the close
// frame) and nothing else.
//
// The server runs its own asio loop: on its own thread inside troupe-sim
// (which stays single-threaded: the bridge only copies bytes between
// sockets), or on the caller's thread in troupe-view.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "wire/frame.h"
#include "wire/noise/client_keys.h"

namespace troupe::viewer {

struct ViewOptions {
  /// Address the HTTP server binds; loopback unless asked otherwise.
  std::string listen = "127.0.0.1";
  /// HTTP port; 0 picks a free one (see ViewServer::port()).
  uint16_t http_port = 6680;
  /// The node the page is bridged to.
  std::string node_host = "127.0.0.1";
  uint16_t node_port = 6665;
  /// Folder holding index.html, viewer.js, viewer.css.
  std::string web_root;
  /// Applied to every frame a page sends.
  wire::Limits limits;
  /// Open WebSockets at once; more are refused with HTTP 503.
  uint32_t max_sessions = 32;
  /// Page origins ("http://robots.lab:8080") whose WebSockets are accepted
  /// besides the viewer's own page; every other is refused with HTTP 403
  /// (origin_check.h).
  std::vector<std::string> allow_origins;
  /// Asked of every request when set (access_token.h). Empty: the server
  /// makes one if it listens beyond loopback, and none otherwise.
  std::string token;
  /// A secure node: our identity and the node's key (read at open()). The
  /// bridge then runs a Noise session on each page's TCP connection and
  /// passes the page plain frames both ways. Empty: plain TCP.
  wire::noise::ClientKeys keys;
};

/// The folder holding the page's files, found from this executable's place
/// (`<dir of /proc/self/exe>/../share/troupe/viewer`), the same in a build
/// tree (build/<preset>/bin) and an installed one (<prefix>/bin).
std::string default_web_root();

class ViewServer {
 public:
  explicit ViewServer(ViewOptions options);
  ~ViewServer();
  ViewServer(const ViewServer&) = delete;
  ViewServer& operator=(const ViewServer&) = delete;

  /// Resolves the node's address, reads the keys of a secure node and binds
  /// the HTTP port. False with `error` (which says what failed) when any fails.
  bool open(std::string& error);
  /// The bound HTTP port (after open()).
  uint16_t port() const;
  /// "http://ADDR:PORT/" for people to open, with "?token=..." when the
  /// server asks for one.
  std::string url() const;

  /// Serves on the calling thread until stop().
  void run();
  /// Serves on a thread of its own until stop() or destruction.
  void start_thread();
  /// Safe from any thread.
  void stop();

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  std::thread thread_;
};

}  // namespace troupe::viewer
